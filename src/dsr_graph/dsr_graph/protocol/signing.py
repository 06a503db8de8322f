"""Signed DSR messages (our substitute for SROS2, whose plugins the wheels' Fast DDS lacks).

A signed message is the JSON object it always was, with one more member at its end:

    {"seq": 12, ..., "ops": [...], "sig": {"by": "/dsr_server", "ed25519": "<base64>"}}

The signature covers the exact bytes of the object without that member, prefixed by a context:
``dsr-sig-1``, the channel (``dsr/deltas``, ``dsr/transactions``...: a message signed for one
channel is refused on another) and the signer's name. Signing appends text and verifying cuts
it off, so nothing is re-encoded or canonicalised; every JSON reader still reads a signed
message, and ``ros2 topic echo`` shows it as it is. Ed25519: the keys are read from the
keystore's PEM files with ``cryptography`` (formats/keystore.py), and signed and checked with
PyNaCl (libsodium), which verifies 1.6x faster on these machines (every replica checks every
delta). Pure logic; the ROS side is in ``ros/agent.py`` and ``ros/server_node.py``.

A verified message proves who sent it and that it was not changed; it does not prove it is
new: a recorded message can be sent again. Deltas carry their seq (a replica applies each seq
once), requests their id (the server applies each id once), heartbeats their seq and stamp.
"""

from __future__ import annotations

import base64
import binascii
import json
from collections.abc import Mapping
from dataclasses import dataclass

from cryptography.hazmat.primitives import serialization
from cryptography.hazmat.primitives.asymmetric.ed25519 import Ed25519PrivateKey, Ed25519PublicKey
from nacl.exceptions import BadSignatureError
from nacl.signing import SigningKey, VerifyKey

from dsr_graph.exceptions import SignatureRefused

CONTEXT = b"dsr-sig-1"
_NONE = serialization.NoEncryption()
MARK = ',"sig":{"by":'  # how the signature member starts (after at least one other member)
MAX_SIG_MEMBER = 512  # bytes of the signature member at most (a name and 88 base64 characters)


@dataclass(frozen=True)
class Verified:
    """A message whose signature held: who signed it, and the message without the signature."""

    signer: str
    payload: str


def _signed_bytes(channel: str, signer: str, payload: str) -> bytes:
    # surrogateescape: a request that is not UTF-8 (server's raw read) is checked as it came
    text = payload.encode("utf-8", "surrogateescape")
    return b"\n".join((CONTEXT, channel.encode(), signer.encode(), text))


class Signer:
    """Signs with one node's private key, as that node."""

    def __init__(self, name: str, key: Ed25519PrivateKey):
        self.name = name
        raw = serialization.Encoding.Raw
        self._key = SigningKey(key.private_bytes(raw, serialization.PrivateFormat.Raw, _NONE))

    def sign(self, channel: str, payload: str) -> str:
        """``payload`` (a JSON object's text, not empty) with its signature member appended."""
        body = payload.rstrip()
        if not body.endswith("}") or body == "{}":
            raise ValueError("only a non-empty JSON object's text can be signed")
        signature = self._key.sign(_signed_bytes(channel, self.name, body)).signature
        encoded = base64.b64encode(signature).decode()
        return f'{body[:-1]}{MARK}{json.dumps(self.name)},"ed25519":"{encoded}"}}}}'


class Verifier:
    """Checks signatures against the public keys of a keystore (name -> key)."""

    def __init__(self, keys: Mapping[str, Ed25519PublicKey]):
        raw = serialization.Encoding.Raw
        self.keys = {
            name: VerifyKey(key.public_bytes(raw, serialization.PublicFormat.Raw))
            for name, key in keys.items()
        }

    def verify(self, channel: str, text: str, signers: frozenset[str] | None = None) -> Verified:
        """The signer and the payload of ``text``, or ``SignatureRefused`` naming what is wrong.
        ``signers``: the only names allowed to sign on this channel (None: any key's owner)."""
        cut = text.rfind(MARK)
        if cut < 0 or len(text) - cut > MAX_SIG_MEMBER or not text.endswith("}}"):
            raise SignatureRefused("not signed")
        try:
            member = json.loads(text[cut + len(',"sig":') : -1])
            signer, encoded = member["by"], member["ed25519"]
            if set(member) != {"by", "ed25519"} or not isinstance(signer, str):
                raise ValueError
            signature = base64.b64decode(encoded, validate=True)
        except (ValueError, KeyError, TypeError, binascii.Error):
            raise SignatureRefused("a malformed signature") from None
        if signers is not None and signer not in signers:
            raise SignatureRefused(
                f"signed by {signer!r}, who may not sign here (only {', '.join(sorted(signers))})"
            )
        key = self.keys.get(signer)
        if key is None:
            raise SignatureRefused(f"signed by {signer!r}, who has no key in the keystore")
        payload = text[:cut] + "}"
        try:
            key.verify(_signed_bytes(channel, signer, payload), signature)
        except (BadSignatureError, ValueError):  # (ValueError: not 64 bytes)
            raise SignatureRefused(
                f"the signature of {signer!r} does not match (forged, or changed on the way)"
            ) from None
        return Verified(signer, payload)
