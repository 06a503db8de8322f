"""CGAmed's results store: finished tests in SQLite (pure; no ROS).

Default path: $XDG_DATA_HOME/clarc/cgamed.sqlite (usually ~/.local/share/clarc/cgamed.sqlite);
``--db`` / the ``db`` parameter change it. Each stored test is committed with
``synchronous=FULL`` before it is acknowledged, so an acknowledged result survives any crash.
Storing the same test again (same patient and start time) returns the id it already has.

Tables: patients (a record per patient: id and name), tests (one row per test: which test, whose,
with its whole result as JSON), items (one row per item of a questionnaire, in test order) and
notifications (what the clinician was told).

The schema and its versions: ``store_schema.py``; the checks a result passes before it is
stored: ``result_checks.py``; the patients' records: ``patients_table.py``; the accounts and the
audit trail: ``accounts_table.py`` (both parts of ``ResultsStore``).

Questionnaire results are checked against their test definition (any test in
clarc_agents/definitions); an item that ``needs_clinician`` waits for the clinician's score
(``ResultsStore.score``), and the result is ``complete`` once none waits.
"""

from __future__ import annotations

import json
import os
import sqlite3
from datetime import UTC, datetime
from pathlib import Path
from typing import Any

from clarc_agents import definitions
from clarc_sim.exceptions import (
    AlreadyValidated,
    InvalidResult,
    ResultChanged,
    UnknownTest,
)
from clarc_sim.hospital.accounts_table import AccountsTable
from clarc_sim.hospital.patients_table import PatientsTable
from clarc_sim.hospital.result_checks import (
    TIMED,
    band_of,
    check_result,
    provisional,
    waiting_for_clinician,
)
from clarc_sim.hospital.store_schema import migrate
from dsr_graph.formats.default_paths import data_path

# The Barthel test's items keep the fields they had in `clarc results --json` before tests were
# data files, and whether the clinician scores them (an answer the robot could not understand)
ITEM_FIELDS = {"barthel": ("item", "points", "via", "attempts", "needs_clinician")}
EVIDENCE = ("heard", "audio")  # an item's, listed whenever it has them


def default_db() -> str:
    """$XDG_DATA_HOME/clarc/cgamed.sqlite"""
    return data_path("clarc", "cgamed.sqlite")


class ResultsStore(PatientsTable, AccountsTable):
    def __init__(self, path: str, shared: bool = False):
        """``shared``: the connection is made in one thread and used in another (CGAmed makes it
        at start-up and uses it from its ROS thread); it is still used by one thread at a time."""
        self.path = str(path)
        Path(self.path).parent.mkdir(parents=True, exist_ok=True)
        self.db = sqlite3.connect(self.path, timeout=10, check_same_thread=not shared)
        if self.path != ":memory:":  # patients' data: the file is its user's alone, even when an
            os.chmod(self.path, 0o600)  # older version created it open
        self.db.execute("PRAGMA journal_mode=WAL")
        self.db.execute("PRAGMA synchronous=FULL")
        columns = [row[1] for row in self.db.execute("PRAGMA table_info(notifications)")]
        if columns and "test_id" not in columns:  # written before notifications named a test
            with self.db:
                self.db.execute("ALTER TABLE notifications ADD COLUMN test_id INTEGER")
        self.migrated_from = migrate(self.db)

    def close(self) -> None:
        self.db.close()

    def store(self, result: dict[str, Any]) -> int:
        check_result(result)
        now = datetime.now(UTC).isoformat(timespec="seconds")
        with self.db:  # one transaction: the test and its items, or nothing
            row = self.db.execute(
                "SELECT id FROM tests WHERE patient = ? AND started = ?",
                (result["patient"], result["started"]),
            ).fetchone()
            if row is not None:
                return row[0]
            patient_id = self._patient_of(result, now)
            cur = self.db.execute(
                "INSERT INTO tests (test, patient, started, finished, total, band,"
                " clinician_called, person_lost, result_json, stored, patient_id)"
                " VALUES (?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?)",
                (
                    result.get("test", "barthel"),
                    result["patient"],
                    result["started"],
                    result.get("finished"),
                    result.get("total"),
                    # the listing's column: the band, or provisional while doubtful items wait
                    result["band"] if result["band"] is not None else "provisional",
                    int(bool(result.get("clinician_called"))),
                    int(bool(result.get("person_lost"))),
                    json.dumps(result),
                    now,
                    patient_id,
                ),
            )
            test_id = cur.lastrowid
            self.db.executemany(  # none for a timed test
                "INSERT INTO items (test_id, position, item, points, via, attempts)"
                " VALUES (?, ?, ?, ?, ?, ?)",
                [
                    (test_id, n, i["item"], i["points"], i["via"], i["attempts"])
                    for n, i in enumerate(result.get("items", []), 1)
                ],
            )
        return test_id

    # ------------------------------------------------------------------ the clinician
    def score(
        self, test_id: int, item: str, points: int, clinician: str, when: str | None = None
    ) -> dict[str, Any]:
        """The clinician scores an item that ``needs_clinician`` (a drawing), before the result
        is validated; the total, the band and ``complete`` follow. The result as it is now."""
        clinician = clinician.strip()
        if not clinician:
            raise InvalidResult("a score needs the clinician's name")
        when = when or datetime.now(UTC).isoformat(timespec="seconds")
        with self.db:
            row = self.db.execute(
                "SELECT test, result_json, validated_by, validated_at FROM tests WHERE id = ?",
                (test_id,),
            ).fetchone()
            if row is None:
                raise UnknownTest(f"no test {test_id}")
            test, result_json, by, at = row
            if by is not None:
                raise AlreadyValidated(
                    f"test {test_id} was validated by {by} at {at}: it cannot change"
                )
            if test == TIMED:
                raise InvalidResult(f"test {test_id} is timed: it has no items to score")
            definition = definitions.load(test)
            result = json.loads(result_json)
            flagged = [i["item"] for i in result["items"] if i.get("needs_clinician")]
            waits = [i.key for i in definition.items if i.needs_clinician or i.key in flagged]
            if item not in waits:
                raise InvalidResult(
                    f"{item!r} is not scored by the clinician in this {definition.title} "
                    f"(those are: {', '.join(waits) or 'none'})"
                )
            spec = definition.item(item)
            if isinstance(points, bool) or not isinstance(points, int) or points not in spec.points:
                raise InvalidResult(
                    f"{item}: a score is one of {list(spec.points)}, got {points!r}"
                )
            entry = result["items"][definition.order.index(item)]
            entry.update(points=points, scored_by=clinician, scored_at=when)
            result["total"] = sum(i["points"] for i in result["items"] if i["points"] is not None)
            result["band"] = band_of(definition, result["items"])
            result |= provisional(definition, result["items"])
            result["complete"] = not waiting_for_clinician(definition, result["items"])
            if result.get("unanswered") and entry.get("via") is None:
                result["unanswered"] = [k for k in result["unanswered"] if k != item]
            self.db.execute(
                "UPDATE tests SET total = ?, band = ?, result_json = ?, version = version + 1 "
                "WHERE id = ? AND validated_by IS NULL",
                (result["total"], result["band"] or "provisional", json.dumps(result), test_id),
            )
            self.db.execute(
                "UPDATE items SET points = ? WHERE test_id = ? AND item = ?",
                (points, test_id, item),
            )
            # every score is kept: a re-score adds one, the result shows the latest
            self.db.execute(
                "INSERT INTO scores (test_id, item, points, scored_by, scored_at, version) "
                "SELECT ?, ?, ?, ?, ?, version FROM tests WHERE id = ?",
                (test_id, item, points, clinician, when, test_id),
            )
        return self.test(test_id)

    def validate(
        self, test_id: int, clinician: str, when: str | None = None, version: int | None = None
    ) -> dict[str, Any]:
        """The clinician validates a stored result: stored with their name and the time, once;
        after it the result cannot change. ``version``: the version of the result they saw
        (``ResultChanged`` if it changed since). ``InvalidResult`` says why it cannot be done."""
        clinician = clinician.strip()
        if not clinician:
            raise InvalidResult("a validation needs the clinician's name")
        when = when or datetime.now(UTC).isoformat(timespec="seconds")
        with self.db:
            result = self.test(test_id)
            if result["validated_by"] is not None:
                raise AlreadyValidated(
                    f"test {test_id} was validated by {result['validated_by']} at "
                    f"{result['validated_at']}"
                )
            waiting = []
            if result["test"] != TIMED:
                waiting = waiting_for_clinician(definitions.load(result["test"]), result["items"])
            if waiting:
                raise InvalidResult(f"test {test_id}: score {', '.join(waiting)} first")
            if version is not None and version != result["version"]:
                raise ResultChanged(
                    f"test {test_id} changed since you saw it (version {version}, now "
                    f"{result['version']}): look at it again before validating"
                )
            self.db.execute(
                "UPDATE tests SET validated_by = ?, validated_at = ? "
                "WHERE id = ? AND validated_by IS NULL",
                (clinician, when, test_id),
            )
        return {"validated_by": clinician, "validated_at": when, "version": result["version"]}

    def notify(self, kind: str, message: str, test_id: int | None = None) -> None:
        with self.db:
            self.db.execute(
                "INSERT INTO notifications (time, kind, message, test_id) VALUES (?, ?, ?, ?)",
                (datetime.now(UTC).isoformat(timespec="seconds"), kind, message, test_id),
            )

    def notified(self, kind: str, test_id: int) -> bool:
        """The clinician was already told ``kind`` about this test (a result sent again)."""
        row = self.db.execute(
            "SELECT 1 FROM notifications WHERE kind = ? AND test_id = ?", (kind, test_id)
        ).fetchone()
        return row is not None

    def tests(self) -> list[dict[str, Any]]:
        """Every stored test, oldest first, in the `clarc results --json` shape."""
        return [_as_listed(row) for row in self.db.execute(f"{LISTED} ORDER BY id")]

    def test(self, test_id: int) -> dict[str, Any]:
        """One stored test, as ``tests`` lists it; ``UnknownTest`` if there is none."""
        row = self.db.execute(f"{LISTED} WHERE id = ?", (test_id,)).fetchone()
        if row is None:
            raise UnknownTest(f"no test {test_id}")
        return _as_listed(row)

    def notifications(self) -> list[dict[str, Any]]:
        return [
            {"time": t, "kind": k, "message": m}
            for t, k, m in self.db.execute(
                "SELECT time, kind, message FROM notifications ORDER BY id"
            )
        ]


def _item_fields(definition, item: dict[str, Any]) -> dict[str, Any]:
    """An item of a stored result with its maximum and whether the clinician scores it (a
    result stored before items said so gets them from its definition)."""
    spec = definition.item(item["item"])
    return {"max": spec.max, "needs_clinician": spec.needs_clinician, **item}


# what ``tests`` and ``test`` read of a stored test
LISTED = (
    "SELECT id, test, result_json, validated_by, validated_at, patient_id, version, "
    "(SELECT json_group_array(json_object('item', item, 'points', points, 'scored_by', "
    "scored_by, 'scored_at', scored_at, 'version', version)) FROM "
    "(SELECT * FROM scores WHERE scores.test_id = tests.id ORDER BY scores.id)) FROM tests"
)


def _as_listed(row: tuple) -> dict[str, Any]:
    """A stored test in the `clarc results --json` shape."""
    test_id, test, result_json, by, at, patient_id, version, scores = row
    result = json.loads(result_json)
    validation = {
        "validated_by": by,
        "validated_at": at,
        "patient_id": patient_id,
        "version": version,
        "scores": json.loads(scores),  # every score given, the earlier ones kept
    }
    if test == TIMED:
        return {
            "id": test_id,
            "test": test,
            "patient": result["patient"],
            "started": result["started"],
            "finished": result.get("finished"),
            "outcome": result["outcome"],
            "tug_seconds": result["tug_seconds"],
            "reaction_seconds": result["reaction_seconds"],
            "phases": result["phases"],
            "band": result["band"],
            "fall_risk": result["fall_risk"],
            "trials": int(result.get("trials", 1)),
            "void_reasons": result.get("void_reasons", []),
            "person_lost": bool(result.get("person_lost")),
            "person_lost_count": int(result.get("person_lost_count", 0)),
            **validation,
        }
    definition = definitions.load(test)
    items = [_item_fields(definition, i) for i in result["items"]]
    complete = not waiting_for_clinician(definition, items)
    if test in ITEM_FIELDS:
        items = [{k: i[k] for k in ITEM_FIELDS[test] + EVIDENCE if k in i} for i in items]
    return {
        "id": test_id,
        "test": test,
        "patient": result["patient"],
        "started": result["started"],
        "finished": result.get("finished"),
        "total": result["total"],
        "max_total": definition.max_total,
        "band": result["band"],
        **provisional(definition, items),
        "complete": complete,
        "items": items,
        "unanswered": result.get("unanswered", []),
        "clinician_called": bool(result.get("clinician_called")),
        "person_lost": bool(result.get("person_lost")),
        "person_lost_count": int(result.get("person_lost_count", 0)),
        **validation,
    }
