"""CGAmed's results store across versions and tests: stores written before schema versions and at
version 2 (kept as fixtures, written by that code) open, migrate and lose nothing; Get Up & Go
results are stored with their time and phases and refused when they do not add up."""

import json
import shutil
import sqlite3
from pathlib import Path

import pytest

from clarc_sim.exceptions import InvalidResult
from clarc_sim.hospital import store_schema
from clarc_sim.hospital.results_store import ResultsStore
from clarc_sim.hospital.store_schema import VERSION

BEFORE_VERSIONS = Path(__file__).resolve().parents[1] / "fixtures" / "cgamed_before_versions.sqlite"
# written by the code of version 2 (before patients were records): two Barthel results, one of
# them validated, a Get Up & Go result and a notification
VERSION_2 = Path(__file__).resolve().parents[1] / "fixtures" / "cgamed_version_2.sqlite"


def rows(path):
    db = sqlite3.connect(path)
    try:
        return {
            table: db.execute(f"SELECT * FROM {table} ORDER BY 1, 2").fetchall()
            for table in ("items", "notifications")
        } | {"tests": db.execute("SELECT id, result_json, stored FROM tests").fetchall()}
    finally:
        db.close()


def test_a_store_written_before_versions_migrates_and_keeps_everything(tmp_path):
    path = tmp_path / "cgamed.sqlite"
    shutil.copy(BEFORE_VERSIONS, path)
    before = rows(path)
    store = ResultsStore(path)
    assert store.migrated_from == 0
    tests = store.tests()
    assert [t["test"] for t in tests] == ["barthel", "barthel"]
    assert [(t["patient"], t["total"], t["band"]) for t in tests] == [
        ("Carlos", 85, "moderate"),
        ("Ana", 100, "independent"),
    ]
    assert tests[0]["unanswered"] == ["grooming"] and tests[0]["person_lost"]
    # version 3: each patient became a record, and their tests name it
    assert [p["name"] for p in store.patients()] == ["Carlos", "Ana"]
    assert [t["patient_id"] for t in tests] == [1, 2]
    # a Barthel result reads as it always did; nothing of it waits for the clinician
    assert set(tests[0]["items"][0]) == {"item", "points", "via", "attempts", "needs_clinician"}
    assert tests[0]["complete"] is True
    store.close()
    assert rows(path) == before  # every row as it was
    assert sqlite3.connect(path).execute("PRAGMA user_version").fetchone() == (VERSION,)
    assert ResultsStore(path).migrated_from == VERSION  # once


def test_a_migration_that_fails_leaves_the_store_as_it_was(tmp_path, monkeypatch):
    path = tmp_path / "cgamed.sqlite"
    shutil.copy(BEFORE_VERSIONS, path)
    before = rows(path)
    broken = {**store_schema.MIGRATIONS, 1: [*store_schema.MIGRATIONS[1][:3], "NOT SQL"]}
    monkeypatch.setattr(store_schema, "MIGRATIONS", broken)
    with pytest.raises(sqlite3.OperationalError):
        ResultsStore(path)
    assert rows(path) == before
    assert sqlite3.connect(path).execute("PRAGMA user_version").fetchone() == (0,)


def test_a_store_from_a_newer_clarc_is_refused(tmp_path):
    path = tmp_path / "cgamed.sqlite"
    ResultsStore(path).close()
    db = sqlite3.connect(path)
    db.execute(f"PRAGMA user_version = {VERSION + 1}")
    db.close()
    with pytest.raises(InvalidResult, match="newer"):
        ResultsStore(path)


def gug(**changes):
    doc = {
        "test": "get_up_and_go",
        "patient": "Carlos",
        "started": "2026-11-24T10:00:00+00:00",
        "outcome": "timed",
        "tug_seconds": 14.2,
        "reaction_seconds": 0.8,
        "phases": {
            "rise": 1.6,
            "walk_out": 4.0,
            "turn": 2.1,
            "walk_back": 4.0,
            "sit": 1.5,
            "still": 0.2,
        },
        "band": "mostly independent",
        "fall_risk": True,
    }
    doc.update(changes)
    return doc


def test_a_get_up_and_go_result_is_stored_with_its_time_and_phases(tmp_path):
    store = ResultsStore(tmp_path / "cgamed.sqlite")
    first = store.store(gug())
    assert store.store(gug()) == first
    [stored] = store.tests()
    assert stored["test"] == "get_up_and_go" and stored["tug_seconds"] == 14.2
    assert list(stored["phases"]) == ["rise", "walk_out", "turn", "walk_back", "sit", "still"]
    assert stored["band"] == "mostly independent" and stored["fall_risk"] is True
    assert stored["outcome"] == "timed" and stored["reaction_seconds"] == 0.8


def test_a_patient_unable_to_perform_is_stored_with_each_trial_s_reason(tmp_path, capsys):
    store = ResultsStore(tmp_path / "cgamed.sqlite")
    reasons = [f"trial {n}: the patient was not seated at go" for n in (1, 2, 3)]
    unable = gug(
        outcome="unable",
        tug_seconds=None,
        reaction_seconds=None,
        phases=None,
        band="unable to perform",
        trials=3,
        void_reasons=reasons,
    )
    store.store(unable)
    [stored] = store.tests()
    assert stored["outcome"] == "unable" and stored["void_reasons"] == reasons
    assert stored["tug_seconds"] is None and stored["fall_risk"] is True
    # as `clarc results` lists it for the clinician
    from clarc_sim.console.clarc_cli import main as clarc

    assert clarc(["results", "--db", str(tmp_path / "cgamed.sqlite")]) == 0
    listed = capsys.readouterr().out
    assert "Get Up & Go unable to perform" in listed and "[fall risk]" in listed
    assert all(reason in listed for reason in reasons)
    with pytest.raises(InvalidResult, match="reason of each void trial"):
        store.store(dict(unable, started="2026-11-25T10:00:00+00:00", void_reasons=[]))
    with pytest.raises(InvalidResult, match="no tug_seconds"):
        store.store(dict(unable, started="2026-11-25T10:00:00+00:00", tug_seconds=3.0))


@pytest.mark.parametrize(
    "changes, error",
    [
        ({"band": "normal"}, "do not match"),
        ({"fall_risk": False}, "do not match"),
        ({"tug_seconds": -3}, "result.tug_seconds: -3 is not valid"),
        ({"phases": {"rise": 1.0}}, "rise, walk_out, turn, walk_back, sit, still"),
        ({"reaction_seconds": 3.0}, "add up to 16.40 s, not tug_seconds 14.2"),
        ({"outcome": "maybe"}, "result.outcome: 'maybe' is not one of"),
        ({"test": "tug"}, "unknown test 'tug'"),
    ],
)
def test_a_get_up_and_go_result_that_does_not_add_up_is_refused(tmp_path, changes, error):
    store = ResultsStore(tmp_path / "cgamed.sqlite")
    with pytest.raises(InvalidResult, match=error):
        store.store(gug(**changes))
    assert store.tests() == []


def test_a_result_is_validated_once_with_the_clinician_s_name_and_time(tmp_path):
    path = tmp_path / "cgamed.sqlite"
    shutil.copy(BEFORE_VERSIONS, path)  # a store from before validation: it gains it
    store = ResultsStore(path)
    assert [t["validated_by"] for t in store.tests()] == [None, None]
    done = store.validate(1, " Dr. Ruiz ", when="2026-11-24T18:00:00+00:00")
    assert done == {
        "validated_by": "Dr. Ruiz",
        "validated_at": "2026-11-24T18:00:00+00:00",
        "version": 1,
    }
    first = store.tests()[0]
    assert (first["validated_by"], first["validated_at"]) == ("Dr. Ruiz", done["validated_at"])
    with pytest.raises(InvalidResult, match="was validated by Dr. Ruiz at 2026-11-24T18:00"):
        store.validate(1, "Dr. Gil")
    with pytest.raises(InvalidResult, match="clinician's name"):
        store.validate(2, "  ")
    with pytest.raises(InvalidResult, match="no test 9"):
        store.validate(9, "Dr. Gil")
    assert store.tests()[1]["validated_by"] is None  # refusals change nothing
    store.close()
    reopened = ResultsStore(path)
    assert reopened.tests()[0]["validated_by"] == "Dr. Ruiz"  # committed


def test_a_store_of_version_2_migrates_keeping_its_validations_and_gains_patients(tmp_path):
    path = tmp_path / "cgamed.sqlite"
    shutil.copy(VERSION_2, path)
    before = rows(path)
    store = ResultsStore(path)
    assert store.migrated_from == 2
    tests = store.tests()
    assert [(t["test"], t["patient"], t.get("total")) for t in tests] == [
        ("barthel", "Carlos", 70),
        ("barthel", "Ana", 100),
        ("get_up_and_go", "Carlos", None),
    ]
    assert (tests[1]["validated_by"], tests[1]["validated_at"]) == (
        "Dr. Ruiz",
        "2026-11-23T12:00:00+00:00",
    )
    assert tests[2]["tug_seconds"] == 9.1 and tests[2]["validated_by"] is None
    assert [p["name"] for p in store.patients()] == ["Carlos", "Ana"]
    assert [t["patient_id"] for t in tests] == [1, 2, 1]  # Carlos's two tests, one record
    with pytest.raises(InvalidResult, match="validated by Dr. Ruiz"):
        store.validate(2, "Dr. Gil")
    # version 5: the Get Up & Go result says it was timed, its reaction (what its phases leave
    # of the total) and no time standing still; nothing else of any row changes
    assert tests[2]["outcome"] == "timed" and tests[2]["phases"]["still"] == 0.0
    assert tests[2]["reaction_seconds"] == pytest.approx(
        9.1 - sum(v for k, v in tests[2]["phases"].items() if k != "still"), abs=0.006
    )
    store.close()
    assert without_version_5(rows(path)) == without_version_5(before)  # every row as it was


def without_version_5(found):
    tests = []
    for test_id, result_json, stored in found["tests"]:
        result = json.loads(result_json)
        for key in ("outcome", "reaction_seconds", "void_reasons"):
            result.pop(key, None)
        if isinstance(result.get("phases"), dict):
            result["phases"].pop("still", None)
        tests.append((test_id, result, stored))
    return found | {"tests": tests}


def barthel_result(**changes):
    from barthel_items import DEFINITION, ORDER

    from clarc_agents.questionnaire.record import QuestionnaireRecord

    r = QuestionnaireRecord(DEFINITION, "Carlos", "2026-11-24T10:00:00")
    for k in ORDER:
        r.answer(k, 0, "voice")
        r.items[k].attempts = 1
    doc = r.to_json()
    doc.update(changes)
    return doc


@pytest.mark.parametrize(
    "result, named",
    [
        (
            barthel_result(
                items=[
                    {k: v for k, v in i.items() if k != "attempts"}
                    for i in barthel_result()["items"]
                ]
            ),
            "result.items[0]: 'attempts' is a required property",
        ),
        (
            barthel_result(patient={"name": "Carlos"}),
            "result.patient: {'name': 'Carlos'} is not of type 'string'",
        ),
        (barthel_result(patient=""), "result.patient: '' should be non-empty"),
        (
            barthel_result(forged=True),
            "Additional properties are not allowed ('forged' was unexpected)",
        ),
        (barthel_result(total="0"), "result.total: '0' is not of type 'integer'"),
        (gug(phases={**gug()["phases"], "rise": float("nan")}), "not finite"),
        (gug(tug_seconds=float("inf")), "not finite"),
        (gug(trials=-1), "result.trials: -1 is less than the minimum of 0"),
        ([1, 2], "a result is a JSON object"),
    ],
)
def test_a_result_that_breaks_the_schema_is_refused_by_name_and_nothing_is_stored(
    tmp_path, result, named
):
    store = ResultsStore(tmp_path / "cgamed.sqlite")
    with pytest.raises(InvalidResult) as refused:
        store.store(result)
    assert named in str(refused.value)
    assert store.tests() == [] and store.patients() == []


def test_the_results_store_is_its_user_s_alone(tmp_path):
    ResultsStore(tmp_path / "cgamed.sqlite").close()
    assert (tmp_path / "cgamed.sqlite").stat().st_mode & 0o777 == 0o600
