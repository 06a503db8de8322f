"""The DSR server's rules without ROS (ros/server_node.py only calls them): how it starts from its
stored state or a world (protocol/state_boot.py), on disk before anyone sees a change
(protocol/acceptance.py), and whose request it is (protocol/attribution.py)."""

from __future__ import annotations

import json

import pytest

from dsr_graph.exceptions import StateMismatch
from dsr_graph.formats.keystore import Keystore
from dsr_graph.formats.state_store import StateStore
from dsr_graph.model.graph import Graph
from dsr_graph.model.policy import OPEN
from dsr_graph.protocol.acceptance import journal_then_broadcast
from dsr_graph.protocol.attribution import attribute
from dsr_graph.protocol.identity import Sender
from dsr_graph.protocol.security import Security
from dsr_graph.protocol.server_core import ServerCore
from dsr_graph.protocol.state_boot import boot_state

pytestmark = pytest.mark.unit

INSERT = {
    "agent": "/speech",
    "id": "s-1",
    "ops": [{"op": "insert_node", "name": "a", "type": "cup"}],
}


def opened(tmp_path) -> StateStore:
    store = StateStore(tmp_path / "state")
    store.open()
    return store


def world(tmp_path, name: str) -> str:
    path = tmp_path / f"{name}.json"
    doc = {"format": "dsr-graph", "version": 1, "kind": "world", "units": {"length": "m"}}
    doc |= {"nodes": [{"id": 1, "name": name, "type": "room"}], "edges": []}
    path.write_text(json.dumps(doc))
    return str(path)


def test_a_new_state_is_stored_at_once_and_a_restart_finds_every_accepted_change(tmp_path):
    store = opened(tmp_path)
    boot = boot_state(store, "", Graph().vocabulary, OPEN, {})
    assert boot.core.seq == 0 and "new state" in boot.notes[-1][1]
    delta = boot.core.submit(json.dumps(INSERT), now=1.0)
    journal_then_broadcast(store, [delta], lambda d: None)
    store.close()
    again = boot_state(opened(tmp_path), "", Graph().vocabulary, OPEN, {})
    assert again.core.seq == 1 and "a" in again.core.graph
    assert again.core.accepted_ids["s-1"] == 1  # a request sent again is still known
    assert "restored" in again.notes[-1][1]


def test_a_state_made_from_another_world_is_refused_unless_resumed(tmp_path):
    ward_a, ward_b = world(tmp_path, "ward_a"), world(tmp_path, "ward_b")
    store = opened(tmp_path)
    boot = boot_state(store, ward_a, Graph().vocabulary, OPEN, {})
    journal_then_broadcast(store, [boot.core.submit(json.dumps(INSERT), now=1.0)], lambda d: None)
    store.close()
    with pytest.raises(StateMismatch, match="resume:=true"):
        boot_state(opened(tmp_path), ward_b, Graph().vocabulary, OPEN, {})
    resumed = boot_state(opened(tmp_path), ward_b, Graph().vocabulary, OPEN, {}, resume=True)
    assert resumed.core.seq == 1 and resumed.notes[0][0] == "warning"
    assert "resume:=true" in resumed.notes[0][1]


def test_a_change_is_on_disk_before_anyone_sees_it_and_a_failed_disk_shows_nothing(tmp_path):
    store = opened(tmp_path)
    core = ServerCore(Graph())
    delta = core.submit(json.dumps(INSERT), now=1.0)
    seen = []  # at each broadcast: is the delta in the journal already?
    journal_then_broadcast(store, [delta], lambda d: seen.append(_journalled(store, d["seq"])))
    assert seen == [True]

    class FullDisk(StateStore):
        def flush(self) -> None:
            raise OSError(28, "No space left on device")

    full = FullDisk(tmp_path / "full")
    full.open()
    other = {**INSERT, "id": "s-2", "ops": [{**INSERT["ops"][0], "name": "b"}]}
    second = core.submit(json.dumps(other), now=2.0)
    shown = []
    with pytest.raises(OSError, match="No space"):
        journal_then_broadcast(full, [second], shown.append)
    assert shown == []


def _journalled(store: StateStore, seq: int) -> bool:
    found = []
    store.replay_journal(seq - 1, found.append)
    return [d["seq"] for d in found] == [seq]


@pytest.fixture
def keystore(tmp_path):
    ks, _ = Keystore.init(tmp_path / "ks")
    ks.add("/speech")
    ks.add("/panel")
    return ks


def security(keystore, name: str, mode: str = "enforce") -> Security:
    env = {"DSR_KEYSTORE": str(keystore.root), "DSR_SECURITY": mode}
    return Security.from_environment(name, env)


SPEECH = Sender("/speech")
NOBODY = Sender(None, "two nodes publish on it", ("/speech", "/intruder"))


def test_a_signed_request_is_its_signer_s_on_its_own_topic_only(keystore):
    server = security(keystore, "/dsr_server")
    text = security(keystore, "/speech").sign("dsr/transactions", json.dumps(INSERT))
    mine = attribute(server, text, NOBODY, "dsr/transactions/speech", "speech", tuple)
    assert mine.agent == "/speech" and mine.proven_signer == "/speech" and not mine.alarms
    assert json.loads(mine.payload) == INSERT
    theirs = attribute(server, text, SPEECH, "dsr/transactions/panel", "panel", tuple)
    assert theirs.agent is None and theirs.refusal.rule == "identity"
    assert [a.kind for a in theirs.alarms] == ["identity"]


def test_an_unsigned_request_is_refused_under_enforce_and_taken_with_an_alarm_when_permissive(
    keystore,
):
    text = json.dumps(INSERT)
    topic = "dsr/transactions/speech"
    strangers = lambda: ("/intruder",)  # noqa: E731
    enforced = attribute(
        security(keystore, "/dsr_server"), text, SPEECH, topic, "speech", strangers
    )
    assert enforced.agent is None and enforced.refusal.rule == "signature"
    assert enforced.alarms[0].intruders == ("/intruder",) and enforced.alarms[0].refused
    permissive = security(keystore, "/dsr_server", "permissive")
    taken = attribute(permissive, text, SPEECH, topic, "speech", strangers)
    assert taken.agent == "/speech" and not taken.alarms[0].refused
    unknown = attribute(permissive, text, NOBODY, topic, "speech", strangers)
    assert unknown.agent is None and [a.kind for a in unknown.alarms] == ["signature", "identity"]


def test_with_security_off_the_ros_graph_s_word_is_all_there_is():
    off = Security()
    assert attribute(off, "{}", SPEECH, "t", "speech", tuple).agent == "/speech"
    refused = attribute(off, "{}", NOBODY, "t", "speech", tuple)
    assert refused.refusal.rule == "identity" and refused.alarms[0].intruders == NOBODY.intruders
