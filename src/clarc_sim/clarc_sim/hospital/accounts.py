"""Who may do what on the clinician's dashboard (pure; no web, no ROS).

Roles, each with what it may do:

    technician   add patients, press Start (and read everything the dashboard shows)
    clinician    what a technician does, and score items and validate results
    admin        manage users (add, disable) and read the audit trail

Passwords are hashed with Argon2id (argon2-cffi's defaults, its own encoded form with the salt
and the parameters); a hash made with older parameters is made again at the next login. Failed
logins are throttled per user name and per client address (``LoginThrottle``).
"""

from __future__ import annotations

import functools
import time
from dataclasses import dataclass, field
from typing import Any

from argon2 import PasswordHasher
from argon2.exceptions import InvalidHashError, VerificationError, VerifyMismatchError

from clarc_sim.exceptions import AccountError

TECHNICIAN, CLINICIAN, ADMIN = "technician", "clinician", "admin"
MAY = {
    "add_patient": {TECHNICIAN, CLINICIAN},
    "start": {TECHNICIAN, CLINICIAN},
    "score": {CLINICIAN},
    "validate": {CLINICIAN},
    "manage_users": {ADMIN},
    "read_audit": {ADMIN},
}
MIN_PASSWORD = 10  # characters
MAX_PASSWORD = 1024  # characters: Argon2 would hash more, but no one types it

_hasher = PasswordHasher()


@functools.cache
def _dummy() -> str:
    """Verified against when a name has no account, so that a wrong name takes as long as a
    wrong password (the time does not tell which names exist). Made at the first login, whatever
    name it gives, not at import: every CGAmed start paid an Argon2 hash (0.16 s)."""
    return _hasher.hash("not a password of anyone's")


def may(role: str, action: str) -> bool:
    return role in MAY.get(action, ())


def check_password(password: str) -> str:
    if not isinstance(password, str) or not MIN_PASSWORD <= len(password) <= MAX_PASSWORD:
        raise AccountError(
            f"a password has {MIN_PASSWORD} to {MAX_PASSWORD} characters (a passphrase is best)"
        )
    return password


def hash_password(password: str) -> str:
    return _hasher.hash(check_password(password))


@dataclass(frozen=True)
class LoginOutcome:
    user: dict[str, Any] | None  # name and role when the login holds
    new_hash: str | None = None  # a rehash to store (Argon2's parameters changed)


def verify_login(account: dict[str, Any] | None, password: str) -> LoginOutcome:
    """The account's name and role if ``password`` is its password and it is not disabled."""
    if not isinstance(password, str) or len(password) > MAX_PASSWORD:
        return LoginOutcome(None)
    dummy = _dummy()  # before the name is looked at: the first login costs alike either way
    encoded = account["password_hash"] if account is not None else dummy
    try:
        _hasher.verify(encoded, password)
    except (VerifyMismatchError, VerificationError, InvalidHashError):
        return LoginOutcome(None)
    if account is None or account["disabled"]:
        return LoginOutcome(None)
    rehash = _hasher.hash(password) if _hasher.check_needs_rehash(encoded) else None
    return LoginOutcome({"name": account["name"], "role": account["role"]}, rehash)


@dataclass
class LoginThrottle:
    """After ``free`` failures of a user name or a client address within ``window`` seconds,
    each further try waits twice as long as the one before (1 s, 2 s, 4 s... up to ``longest``);
    a login that holds clears the name's count. In memory: a restart of CGAmed forgets it."""

    free: int = 5
    window: float = 900.0
    longest: float = 900.0
    _failures: dict[str, list[float]] = field(default_factory=dict)

    def wait(self, keys: list[str], now: float | None = None) -> float:
        """Seconds before these keys (a name, an address) may try again; 0: now."""
        now = time.monotonic() if now is None else now
        waits = [0.0]
        for key in keys:
            recent = [t for t in self._failures.get(key, []) if now - t < self.window]
            self._failures[key] = recent
            if len(recent) >= self.free:
                delay = min(self.longest, 2.0 ** (len(recent) - self.free))
                waits.append(max(0.0, recent[-1] + delay - now))
        return max(waits)

    def failed(self, keys: list[str], now: float | None = None) -> None:
        now = time.monotonic() if now is None else now
        for key in keys:
            self._failures.setdefault(key, []).append(now)

    def succeeded(self, key: str) -> None:
        self._failures.pop(key, None)
