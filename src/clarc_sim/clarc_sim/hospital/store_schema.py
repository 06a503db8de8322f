"""The results store's SQLite schema (clarc_sim/hospital/results_store.py) and its migrations.

Tables: patients (a record per patient: id and name), tests (one row per test: which test, whose,
with its whole result as JSON), items (one row per item of a questionnaire, in test order),
scores, users, audit and notifications.

The schema is versioned (SQLite's ``user_version``): a store written by an older version is
migrated when it is opened, in one transaction, keeping every row (``MIGRATIONS``). Version 0 is
the store before versions (Barthel only); 1 adds ``tests.test`` and lets a test have no total
(a timed test, the Get Up & Go, has a time instead); 2 adds the clinician's validation
(``validated_by``, ``validated_at``), after which a result cannot change; 3 adds patients as
records (``patients``, ``tests.patient_id``: one record per name already stored); 4 adds who may
do what: the dashboard's accounts (``users``: name, role, Argon2 password hash, disabled), an
append-only audit trail (``audit``: SQLite triggers refuse any UPDATE or DELETE), every score a
clinician gave (``scores``: a re-score keeps the earlier one) and a version per result
(``tests.version``, one more at each score) that a validation names; 5 gives every Get Up & Go
result its ``outcome`` (timed or unable), ``reaction_seconds``, time standing still (``phases``
``still``) and ``void_reasons`` (a result stored before was timed, with no pauses, and its
reaction is what its phases leave of the total).
"""

from __future__ import annotations

import sqlite3

from clarc_sim.exceptions import InvalidResult

VERSION = 5
PATIENTS = """CREATE TABLE IF NOT EXISTS patients (
    id INTEGER PRIMARY KEY AUTOINCREMENT,
    name TEXT NOT NULL,
    created TEXT NOT NULL
)"""
SCHEMA = f"""
{PATIENTS};
CREATE TABLE IF NOT EXISTS tests (
    id INTEGER PRIMARY KEY AUTOINCREMENT,
    test TEXT NOT NULL DEFAULT 'barthel',
    patient TEXT NOT NULL,
    started TEXT NOT NULL,
    finished TEXT,
    total INTEGER,
    band TEXT NOT NULL,
    clinician_called INTEGER NOT NULL,
    person_lost INTEGER NOT NULL,
    result_json TEXT NOT NULL,
    stored TEXT NOT NULL,
    validated_by TEXT,
    validated_at TEXT,
    patient_id INTEGER REFERENCES patients(id),
    version INTEGER NOT NULL DEFAULT 1,
    UNIQUE (patient, started)
);
CREATE TABLE IF NOT EXISTS items (
    test_id INTEGER NOT NULL REFERENCES tests(id),
    position INTEGER NOT NULL,
    item TEXT NOT NULL,
    points INTEGER,
    via TEXT,
    attempts INTEGER NOT NULL,
    PRIMARY KEY (test_id, position)
);
CREATE TABLE IF NOT EXISTS notifications (
    id INTEGER PRIMARY KEY AUTOINCREMENT,
    time TEXT NOT NULL,
    kind TEXT NOT NULL,
    message TEXT NOT NULL,
    test_id INTEGER REFERENCES tests(id)
);
{{ACCOUNTS}}
"""
ACCOUNTS = """CREATE TABLE IF NOT EXISTS users (
    id INTEGER PRIMARY KEY AUTOINCREMENT,
    name TEXT NOT NULL UNIQUE,
    role TEXT NOT NULL CHECK (role IN ('technician', 'clinician', 'admin')),
    password_hash TEXT NOT NULL,
    disabled INTEGER NOT NULL DEFAULT 0,
    created TEXT NOT NULL
);
CREATE TABLE IF NOT EXISTS audit (
    id INTEGER PRIMARY KEY AUTOINCREMENT,
    time TEXT NOT NULL,
    user TEXT NOT NULL,
    action TEXT NOT NULL,
    test_id INTEGER,
    detail TEXT NOT NULL DEFAULT ''
);
CREATE TRIGGER IF NOT EXISTS audit_no_update BEFORE UPDATE ON audit
    BEGIN SELECT RAISE(ABORT, 'the audit trail is append-only'); END;
CREATE TRIGGER IF NOT EXISTS audit_no_delete BEFORE DELETE ON audit
    BEGIN SELECT RAISE(ABORT, 'the audit trail is append-only'); END;
CREATE TABLE IF NOT EXISTS scores (
    id INTEGER PRIMARY KEY AUTOINCREMENT,
    test_id INTEGER NOT NULL REFERENCES tests(id),
    item TEXT NOT NULL,
    points INTEGER NOT NULL,
    scored_by TEXT NOT NULL,
    scored_at TEXT NOT NULL,
    version INTEGER NOT NULL
)"""
SCHEMA = SCHEMA.replace("{ACCOUNTS}", ACCOUNTS)


# version reached -> the statements that reach it from the one before (run in one transaction)
MIGRATIONS = {
    1: [
        """CREATE TABLE tests_v1 (
            id INTEGER PRIMARY KEY AUTOINCREMENT,
            test TEXT NOT NULL DEFAULT 'barthel',
            patient TEXT NOT NULL,
            started TEXT NOT NULL,
            finished TEXT,
            total INTEGER,
            band TEXT NOT NULL,
            clinician_called INTEGER NOT NULL,
            person_lost INTEGER NOT NULL,
            result_json TEXT NOT NULL,
            stored TEXT NOT NULL,
            UNIQUE (patient, started))""",
        """INSERT INTO tests_v1 (id, test, patient, started, finished, total, band,
            clinician_called, person_lost, result_json, stored)
            SELECT id, 'barthel', patient, started, finished, total, band, clinician_called,
            person_lost, result_json, stored FROM tests""",
        "DROP TABLE tests",
        "ALTER TABLE tests_v1 RENAME TO tests",
    ],
    2: [
        "ALTER TABLE tests ADD COLUMN validated_by TEXT",
        "ALTER TABLE tests ADD COLUMN validated_at TEXT",
    ],
    3: [
        PATIENTS,
        "ALTER TABLE tests ADD COLUMN patient_id INTEGER REFERENCES patients(id)",
        """INSERT INTO patients (name, created)
            SELECT patient, MIN(stored) FROM tests GROUP BY patient ORDER BY MIN(id)""",
        "UPDATE tests SET patient_id = (SELECT id FROM patients WHERE name = tests.patient)",
    ],
    4: [
        "ALTER TABLE tests ADD COLUMN version INTEGER NOT NULL DEFAULT 1",
        # (users, audit and scores come with SCHEMA's CREATE ... IF NOT EXISTS)
    ],
    # Get Up & Go results say their outcome and reaction, and the phases their time standing
    # still: every result before was timed, its phases contiguous from the start of the rise
    # (so the reaction is the rest of the total) and without pauses
    5: [
        """UPDATE tests SET result_json = json_set(result_json,
            '$.outcome', 'timed',
            '$.reaction_seconds', round(json_extract(result_json, '$.tug_seconds')
                - json_extract(result_json, '$.phases.rise')
                - json_extract(result_json, '$.phases.walk_out')
                - json_extract(result_json, '$.phases.turn')
                - json_extract(result_json, '$.phases.walk_back')
                - json_extract(result_json, '$.phases.sit'), 2),
            '$.phases.still', 0.0,
            '$.void_reasons', json('[]'))
            WHERE test = 'get_up_and_go' AND json_extract(result_json, '$.outcome') IS NULL""",
    ],
}


def statements(script: str) -> list[str]:
    """A SQL script's statements, each whole (a trigger's body holds semicolons of its own)."""
    found, current = [], ""
    for piece in script.split(";"):
        current += piece + ";"
        if sqlite3.complete_statement(current):
            if current.strip(" \n;"):
                found.append(current.strip())
            current = ""
    return found


def migrate(db: sqlite3.Connection) -> int:
    """Bring the store to ``VERSION``; the version it had."""
    had = db.execute("PRAGMA user_version").fetchone()[0]
    if had > VERSION:
        raise InvalidResult(f"store schema version {had} is newer than this CLARC's ({VERSION})")
    fresh = db.execute("SELECT 1 FROM sqlite_master WHERE name = 'tests'").fetchone() is None
    steps = [] if fresh else [m for v in range(had + 1, VERSION + 1) for m in MIGRATIONS[v]]
    steps += statements(SCHEMA)  # and the tables a version added
    # one transaction, DDL included (Python's sqlite3 would commit DDL on its own)
    db.execute("BEGIN IMMEDIATE")
    try:
        for statement in steps:
            db.execute(statement)
        db.execute(f"PRAGMA user_version = {VERSION}")
        db.execute("COMMIT")
    except BaseException:
        db.execute("ROLLBACK")
        raise
    return had
