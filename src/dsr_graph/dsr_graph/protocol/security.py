"""What a process of the suite does with signatures, chosen by its environment (pure logic):

    DSR_KEYSTORE=DIR           the keystore (formats/keystore.py)
    DSR_SECURITY=enforce       sign; drop (and alarm on) what the server did not sign, refuse
                               requests not signed by their agent; a writer needs its key
    DSR_SECURITY=permissive    sign when the node has a key; check, but only warn on failures
    DSR_SECURITY=off           neither sign nor check (the default without DSR_KEYSTORE)

Unset, DSR_SECURITY is ``enforce`` when DSR_KEYSTORE is set and ``off`` otherwise: a keystore
given is a keystore used. The channels are the logical names of the DSR's topics and services
(``dsr/deltas``...), so namespaces and remappings do not change what is signed.
"""

from __future__ import annotations

import os
import time
from collections.abc import Mapping
from dataclasses import dataclass, field

from dsr_graph.exceptions import KeystoreError, SignatureRefused
from dsr_graph.formats.keystore import Keystore
from dsr_graph.protocol import topic_names
from dsr_graph.protocol.signing import Signer, Verified, Verifier

ENFORCE, PERMISSIVE, OFF = "enforce", "permissive", "off"
MODES = (ENFORCE, PERMISSIVE, OFF)
KEYSTORE_VAR, SECURITY_VAR = "DSR_KEYSTORE", "DSR_SECURITY"
SERVER_CHANNELS = (
    topic_names.DELTAS,
    topic_names.REJECTIONS,
    topic_names.HEARTBEAT,
    topic_names.DURABLE,
    topic_names.GET_SNAPSHOT,
)
ALARM_EVERY = 5.0  # seconds between alarms (or warnings) about the same thing
RELOAD_EVERY = 5.0  # seconds between readings of the keystore for a signer not known yet


@dataclass
class Security:
    mode: str = OFF
    keystore: Keystore | None = None
    signer: Signer | None = None
    verifier: Verifier | None = None
    _last_alarm: dict[tuple[str, str], float] = field(default_factory=dict)
    _last_reload: float = field(default_factory=time.monotonic)

    @property
    def checks(self) -> bool:
        return self.mode != OFF

    @property
    def server(self) -> str:
        return self.keystore.server if self.keystore is not None else ""

    @classmethod
    def from_environment(cls, node_name: str, env: Mapping[str, str] | None = None) -> Security:
        """The security of the node ``node_name`` (fully qualified); ``KeystoreError`` naming
        the variable for a mode that cannot be had."""
        env = os.environ if env is None else env
        root = env.get(KEYSTORE_VAR, "")
        mode = env.get(SECURITY_VAR, "") or (ENFORCE if root else OFF)
        if mode not in MODES:
            raise KeystoreError(f"{SECURITY_VAR}={mode!r}: it is one of {', '.join(MODES)}")
        if mode == OFF:
            return cls(OFF)
        if not root:
            raise KeystoreError(
                f"{SECURITY_VAR}={mode} needs {KEYSTORE_VAR} (a folder made by dsr keystore init)"
            )
        keystore = Keystore.open(root)
        key = keystore.private_key(node_name)
        signer = Signer(node_name, key) if key is not None else None
        return cls(mode, keystore, signer, Verifier(keystore.public_keys()))

    # ------------------------------------------------------------------ sending
    def sign(self, channel: str, payload: str) -> str:
        return self.signer.sign(channel, payload) if self.signer is not None else payload

    # ------------------------------------------------------------------ receiving
    def from_server(self, channel: str, text: str) -> tuple[str | None, str]:
        """(the text to read, or None to drop it; the problem, "" if none) for a message the
        DSR server alone may send on ``channel``."""
        return self._open(channel, text, frozenset({self.server}) if self.checks else None)

    def from_member(self, channel: str, text: str) -> tuple[str | None, str]:
        """The same for a message any keystore member may sign (alarms)."""
        return self._open(channel, text, None)

    def _open(self, channel, text, signers) -> tuple[str | None, str]:
        if not self.checks:
            return text, ""
        try:
            return self._verify(channel, text, signers).payload, ""
        except SignatureRefused as e:
            return (None if self.mode == ENFORCE else text), f"{channel}: {e}"

    def request(self, text: str) -> Verified | SignatureRefused:
        """Who signed a request (the server's check), or why no one can be said to have."""
        try:
            return self._verify(topic_names.TRANSACTIONS, text, None)
        except SignatureRefused as e:
            return e

    def _verify(self, channel: str, text: str, signers) -> Verified:
        """A node given a key after this process started (``dsr keystore add``) is known
        without a restart: an unknown signer has the keystore read again, at most every
        ``RELOAD_EVERY`` seconds."""
        try:
            return self.verifier.verify(channel, text, signers)
        except SignatureRefused as e:
            now = time.monotonic()
            if "no key in the keystore" not in str(e) or now - self._last_reload < RELOAD_EVERY:
                raise
            self._last_reload = now
            self.verifier = Verifier(self.keystore.public_keys())
            return self.verifier.verify(channel, text, signers)

    def should_alarm(self, key: tuple[str, str], now: float) -> bool:
        """Rate limit: True at most once every ``ALARM_EVERY`` seconds for the same key."""
        if now - self._last_alarm.get(key, -ALARM_EVERY) < ALARM_EVERY:
            return False
        self._last_alarm[key] = now
        return True
