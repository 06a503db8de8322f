"""Signed DSR messages and the keystore, without ROS: what the server signs is read by every
replica exactly as sent; a message changed, replayed on another channel, signed by another key
or not signed at all is refused by name; keys are files only their user can read."""

import json

import pytest

from dsr_graph.exceptions import KeystoreError, SignatureRefused
from dsr_graph.formats.keystore import Keystore
from dsr_graph.formats.safe_json import loads_object
from dsr_graph.protocol.security import ENFORCE, OFF, PERMISSIVE, Security
from dsr_graph.protocol.signing import Signer, Verifier

DELTA = json.dumps({"seq": 7, "agent": "/speech", "ops": [{"op": "x", "é": "ü"}]})


@pytest.fixture
def keystore(tmp_path):
    ks, made = Keystore.init(tmp_path / "ks")
    assert made and ks.add("/speech") and not ks.add("/speech")
    return ks


def signer(ks, name):
    return Signer(name, ks.private_key(name))


def test_a_signed_message_is_the_same_json_with_a_signature_member(keystore):
    text = signer(keystore, "/dsr_server").sign("dsr/deltas", DELTA)
    doc = loads_object(text)
    assert {k: v for k, v in doc.items() if k != "sig"} == json.loads(DELTA)
    assert doc["sig"]["by"] == "/dsr_server" and len(doc["sig"]["ed25519"]) == 88
    opened = Verifier(keystore.public_keys()).verify("dsr/deltas", text, frozenset({"/dsr_server"}))
    assert (opened.signer, opened.payload) == ("/dsr_server", DELTA)


@pytest.mark.parametrize(
    ("change", "named"),
    [
        (lambda t: t.replace('"seq": 7', '"seq": 8'), "does not match"),
        (lambda t: DELTA, "not signed"),
        (lambda t: t.replace('"by":"/dsr_server"', '"by":"/speech"'), "may not sign here"),
        (lambda t: t.replace('"by":"/dsr_server"', '"by":"/ghost"'), "may not sign here"),
        (lambda t: t[:-3] + '!"}}', "a malformed signature"),
        (lambda t: t[:-2] + ',"x":1}}', "a malformed signature"),
    ],
)
def test_a_changed_or_unsigned_message_is_refused_by_name(keystore, change, named):
    text = signer(keystore, "/dsr_server").sign("dsr/deltas", DELTA)
    with pytest.raises(SignatureRefused, match=named):
        Verifier(keystore.public_keys()).verify(
            "dsr/deltas", change(text), frozenset({"/dsr_server"})
        )


def test_a_message_signed_for_one_channel_is_refused_on_another(keystore):
    text = signer(keystore, "/dsr_server").sign("dsr/heartbeat", DELTA)
    with pytest.raises(SignatureRefused, match="does not match"):
        Verifier(keystore.public_keys()).verify("dsr/deltas", text)


def test_an_agent_cannot_sign_as_the_server_with_its_own_key(keystore):
    forged = Signer("/dsr_server", keystore.private_key("/speech")).sign("dsr/deltas", DELTA)
    with pytest.raises(SignatureRefused, match="does not match"):
        Verifier(keystore.public_keys()).verify("dsr/deltas", forged)


def test_security_from_the_environment(keystore):
    root = str(keystore.root)
    assert Security.from_environment("/speech", {}).mode == OFF
    enforced = Security.from_environment("/speech", {"DSR_KEYSTORE": root})
    assert enforced.mode == ENFORCE and enforced.signer.name == "/speech"
    assert enforced.server == "/dsr_server"
    keyless = Security.from_environment("/nobody", {"DSR_KEYSTORE": root})
    assert keyless.signer is None and keyless.sign("dsr/transactions", "{}") == "{}"
    permissive = Security.from_environment(
        "/speech", {"DSR_KEYSTORE": root, "DSR_SECURITY": "permissive"}
    )
    assert permissive.from_server("dsr/deltas", DELTA) == (DELTA, "dsr/deltas: not signed")
    assert enforced.from_server("dsr/deltas", DELTA) == (None, "dsr/deltas: not signed")
    with pytest.raises(KeystoreError, match="DSR_SECURITY='on'"):
        Security.from_environment("/speech", {"DSR_SECURITY": "on", "DSR_KEYSTORE": root})
    with pytest.raises(KeystoreError, match="needs DSR_KEYSTORE"):
        Security.from_environment("/speech", {"DSR_SECURITY": PERMISSIVE})
    with pytest.raises(KeystoreError, match="not a keystore"):
        Security.from_environment("/speech", {"DSR_KEYSTORE": str(keystore.root / "none")})


def test_keys_are_their_user_s_alone_and_names_are_node_names(keystore):
    modes = {p.name: p.stat().st_mode & 0o777 for p in keystore.root.rglob("*")}
    assert set(modes.values()) <= {0o600, 0o700}
    assert keystore.root.stat().st_mode & 0o777 == 0o700
    assert keystore.names() == ["/dsr_server", "/speech"]
    with pytest.raises(KeystoreError, match="not a fully qualified node name"):
        keystore.add("speech")
    with pytest.raises(KeystoreError, match="for the server '/dsr_server', not '/other'"):
        Keystore.init(keystore.root, "/other")


def test_a_node_given_a_key_after_the_start_is_known_without_a_restart(keystore, monkeypatch):
    from dsr_graph.protocol import security

    server = Security.from_environment("/dsr_server", {"DSR_KEYSTORE": str(keystore.root)})
    keystore.add("/late")
    request = Signer("/late", keystore.private_key("/late")).sign("dsr/transactions", DELTA)
    monkeypatch.setattr(security, "RELOAD_EVERY", 0.0)
    assert server.request(request).signer == "/late"
