"""Who may use the dashboard, and what they did: the results store's accounts (``users``: name,
role, Argon2 password hash, disabled) and its append-only audit trail (``audit``: the store's
triggers refuse any change or deletion of a line). A part of ``ResultsStore`` (its ``db``)."""

from __future__ import annotations

import sqlite3
from datetime import UTC, datetime
from typing import Any

from clarc_sim.exceptions import AccountError

ROLES = ("technician", "clinician", "admin")


class AccountsTable:
    db: sqlite3.Connection

    def add_user(self, name: str, role: str, password_hash: str) -> dict[str, Any]:
        """A dashboard account (the hash from ``accounts.hash_password``); ``AccountError`` for
        a taken name, an unknown role, or a name that is not one."""
        name = " ".join(str(name).split())
        if not name or len(name) > 100:
            raise AccountError("a user needs a name (at most 100 characters)")
        if role not in ROLES:
            raise AccountError(f"role {role!r}: it is one of {', '.join(ROLES)}")
        now = datetime.now(UTC).isoformat(timespec="seconds")
        try:
            with self.db:
                self.db.execute(
                    "INSERT INTO users (name, role, password_hash, created) VALUES (?, ?, ?, ?)",
                    (name, role, password_hash, now),
                )
        except sqlite3.IntegrityError:
            raise AccountError(f"there is a user {name!r} already") from None
        return self.user(name)

    def user(self, name: str) -> dict[str, Any] | None:
        """An account with its hash (for logging in), None if there is none."""
        row = self.db.execute(
            "SELECT name, role, password_hash, disabled, created FROM users WHERE name = ?",
            (name,),
        ).fetchone()
        if row is None:
            return None
        return dict(zip(("name", "role", "password_hash", "disabled", "created"), row, strict=True))

    def users(self) -> list[dict[str, Any]]:
        return [
            {"name": n, "role": r, "disabled": bool(d), "created": c}
            for n, r, d, c in self.db.execute(
                "SELECT name, role, disabled, created FROM users ORDER BY id"
            )
        ]

    def set_disabled(self, name: str, disabled: bool = True) -> None:
        with self.db:
            changed = self.db.execute(
                "UPDATE users SET disabled = ? WHERE name = ?", (int(disabled), name)
            ).rowcount
        if not changed:
            raise AccountError(f"there is no user {name!r}")

    def set_password(self, name: str, password_hash: str) -> None:
        """A new hash (Argon2's parameters changed since it was made)."""
        with self.db:
            self.db.execute(
                "UPDATE users SET password_hash = ? WHERE name = ?", (password_hash, name)
            )

    def audit(self, user: str, action: str, test_id: int | None = None, detail: str = "") -> None:
        """One more line of the audit trail (append-only: the store's triggers refuse any
        change or deletion of a line)."""
        with self.db:
            self.db.execute(
                "INSERT INTO audit (time, user, action, test_id, detail) VALUES (?, ?, ?, ?, ?)",
                (datetime.now(UTC).isoformat(timespec="seconds"), user, action, test_id, detail),
            )

    def audit_trail(self, limit: int = 1000) -> list[dict[str, Any]]:
        """The latest lines of the audit trail, newest first."""
        return [
            {"time": t, "user": u, "action": a, "test_id": i, "detail": d}
            for t, u, a, i, d in self.db.execute(
                "SELECT time, user, action, test_id, detail FROM audit ORDER BY id DESC LIMIT ?",
                (limit,),
            )
        ]
