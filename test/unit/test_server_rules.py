"""The DSR server's rules without ROS (ros/server_node.py only calls them): how it starts from its
stored state or a world (protocol/state_boot.py), visible first and durable before acknowledged
(protocol/acceptance.py, formats/group_commit.py), and whose request it is
(protocol/attribution.py)."""

from __future__ import annotations

import json
import threading
import time

import pytest

from dsr_graph.exceptions import StateMismatch
from dsr_graph.formats.group_commit import GroupCommit
from dsr_graph.formats.keystore import Keystore
from dsr_graph.formats.state_store import StateStore
from dsr_graph.model.graph import Graph
from dsr_graph.model.policy import OPEN
from dsr_graph.protocol.acceptance import broadcast_then_commit
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
    commit = GroupCommit(store, boot.core.seq)
    broadcast_then_commit(commit, [delta], lambda d: None)
    commit.close()  # a clean stop commits what was broadcast
    store.close()
    again = boot_state(opened(tmp_path), "", Graph().vocabulary, OPEN, {})
    assert again.core.seq == 1 and "a" in again.core.graph
    assert again.core.accepted_ids["s-1"] == 1  # a request sent again is still known
    assert "restored" in again.notes[-1][1]


def test_a_state_made_from_another_world_is_refused_unless_resumed(tmp_path):
    ward_a, ward_b = world(tmp_path, "ward_a"), world(tmp_path, "ward_b")
    store = opened(tmp_path)
    boot = boot_state(store, ward_a, Graph().vocabulary, OPEN, {})
    commit = GroupCommit(store, boot.core.seq)
    broadcast_then_commit(commit, [boot.core.submit(json.dumps(INSERT), now=1.0)], lambda d: 0)
    commit.close()
    store.close()
    with pytest.raises(StateMismatch, match="resume:=true"):
        boot_state(opened(tmp_path), ward_b, Graph().vocabulary, OPEN, {})
    resumed = boot_state(opened(tmp_path), ward_b, Graph().vocabulary, OPEN, {}, resume=True)
    assert resumed.core.seq == 1 and resumed.notes[0][0] == "warning"
    assert "resume:=true" in resumed.notes[0][1]


def test_a_change_is_seen_before_it_is_durable_and_said_durable_only_once_on_disk(tmp_path):
    store = opened(tmp_path)
    core = ServerCore(Graph())
    told = []
    commit = GroupCommit(store, 0, on_durable=told.append)  # commits when the test says
    delta = core.submit(json.dumps(INSERT), now=1.0)
    seen = []  # at each broadcast: is the delta in the journal already?
    broadcast_then_commit(commit, [delta], lambda d: seen.append(_journalled(store, d["seq"])))
    assert seen == [False] and told == [] and commit.durable == 0 and commit.pending == 1
    assert commit.commit() == 1 and told == [1] and _journalled(store, 1)

    commit.start()  # its own thread: one fdatasync for what gathered
    more = [core.submit(json.dumps(_insert(f"s-{i}", f"n{i}")), now=2.0) for i in range(2, 6)]
    broadcast_then_commit(commit, more, lambda d: None)
    _wait(lambda: commit.durable == 5)
    assert told[0] == 1 and told[-1] == 5 and all(_journalled(store, s) for s in range(1, 6))
    commit.close()


def test_a_server_stopped_between_broadcast_and_commit_restarts_at_its_durable_seq(tmp_path):
    store = opened(tmp_path)
    boot = boot_state(store, "", Graph().vocabulary, OPEN, {})
    commit = GroupCommit(store, boot.core.seq)
    first = boot.core.submit(json.dumps(INSERT), now=1.0)
    broadcast_then_commit(commit, [first], lambda d: None)
    commit.commit()
    second = boot.core.submit(json.dumps(_insert("s-2", "b")), now=2.0)
    shown = []
    broadcast_then_commit(commit, [second], shown.append)
    assert [d["seq"] for d in shown] == [2] and commit.durable == 1
    store.close()  # killed: the commit never comes
    again = boot_state(opened(tmp_path), "", Graph().vocabulary, OPEN, {})
    assert again.core.seq == 1 and "a" in again.core.graph and "b" not in again.core.graph
    assert "s-2" not in again.core.accepted_ids  # sent again, it is applied anew


def test_a_failed_disk_says_nothing_durable_and_calls_for_a_stop(tmp_path):
    class FullDisk(StateStore):
        def write_lines(self, lines) -> None:
            raise OSError(28, "No space left on device")

    full = FullDisk(tmp_path / "full")
    full.open()
    told, failures = [], []
    commit = GroupCommit(full, 0, on_durable=told.append, on_failure=failures.append)
    commit.start()
    core = ServerCore(Graph())
    broadcast_then_commit(commit, [core.submit(json.dumps(INSERT), now=1.0)], lambda d: None)
    _wait(lambda: failures)
    assert "No space" in str(failures[0]) and told == [] and commit.durable == 0
    commit.close()  # does not try again
    assert told == []


def _insert(ident: str, name: str) -> dict:
    return {**INSERT, "id": ident, "ops": [{**INSERT["ops"][0], "name": name}]}


def _wait(condition, seconds: float = 10.0) -> None:
    """Until the commit thread did it (bounded: a busy machine is slow, not stuck)."""
    end = time.monotonic() + seconds
    while not condition():
        assert time.monotonic() < end, "the commit thread did not do it in time"
        threading.Event().wait(0.005)


def _journalled(store: StateStore, seq: int) -> bool:
    """The journal file holds the delta of ``seq`` (read as a restart would)."""
    path = store.dir / "journal.jsonl"
    lines = path.read_text().splitlines() if path.exists() else []
    return any(json.loads(line)["seq"] == seq for line in lines)


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
