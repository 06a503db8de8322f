"""The patients' records of the results store (``patients``: id and name): a result names its
record, a record is made for a name met first. A part of ``ResultsStore`` (its ``db``)."""

from __future__ import annotations

import sqlite3
from datetime import UTC, datetime
from typing import Any

from clarc_sim.exceptions import InvalidResult, UnknownPatient


class PatientsTable:
    db: sqlite3.Connection

    def _patient_of(self, result: dict[str, Any], now: str) -> int:
        """The record a result is for: its ``patient_id`` if the Start named one, else the first
        record with its name, else a new one."""
        given = result.get("patient_id")
        if isinstance(given, int) and not isinstance(given, bool):
            row = self.db.execute("SELECT name FROM patients WHERE id = ?", (given,)).fetchone()
            if row is not None:
                return given
        row = self.db.execute(
            "SELECT id FROM patients WHERE name = ? ORDER BY id LIMIT 1", (result["patient"],)
        ).fetchone()
        if row is not None:
            return row[0]
        cur = self.db.execute(
            "INSERT INTO patients (name, created) VALUES (?, ?)", (result["patient"], now)
        )
        return cur.lastrowid

    def add_patient(self, name: str) -> dict[str, Any]:
        """A new patient record; ``InvalidResult`` for an empty name."""
        name = " ".join(str(name).split())
        if not name:
            raise InvalidResult("a patient needs a name")
        now = datetime.now(UTC).isoformat(timespec="seconds")
        with self.db:
            cur = self.db.execute("INSERT INTO patients (name, created) VALUES (?, ?)", (name, now))
        return {"id": cur.lastrowid, "name": name, "created": now}

    def patients(self) -> list[dict[str, Any]]:
        return [
            {"id": i, "name": n, "created": c}
            for i, n, c in self.db.execute("SELECT id, name, created FROM patients ORDER BY id")
        ]

    def patient(self, patient_id: int) -> dict[str, Any]:
        row = self.db.execute(
            "SELECT id, name, created FROM patients WHERE id = ?", (patient_id,)
        ).fetchone()
        if row is None:
            raise UnknownPatient(f"no patient {patient_id}")
        return {"id": row[0], "name": row[1], "created": row[2]}
