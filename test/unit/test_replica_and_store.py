"""The replica's ordering, gap detection and late join; the state store's durability rules."""

import json

import pytest

from dsr_graph.exceptions import CorruptState, StateDirLocked
from dsr_graph.formats import dsr_json
from dsr_graph.formats.state_store import StateStore
from dsr_graph.model.graph import Graph
from dsr_graph.protocol.replica import Replica
from dsr_graph.protocol.server_core import ServerCore


def make_deltas(n):
    c = ServerCore(Graph())
    snap0 = c.snapshot()
    deltas = [
        c.submit(json.dumps({"ops": [{"op": "insert_node", "name": f"n{i}", "type": "transform"}]}))
        for i in range(n)
    ]
    return snap0, deltas, c


def test_in_order_out_of_order_duplicates_and_gaps():
    snap0, deltas, server = make_deltas(6)
    r = Replica()
    assert r.needs_resync  # never synced
    assert r.receive(deltas[0]) == []  # late join: kept until a snapshot arrives
    assert [d["seq"] for d in r.load_snapshot(snap0)] == [1]
    assert [d["seq"] for d in r.receive(deltas[2])] == []  # gap: 2 is missing
    assert r.needs_resync
    assert [d["seq"] for d in r.receive(deltas[1])] == [2, 3]  # filled: both apply in order
    assert not r.needs_resync
    assert r.receive(deltas[1]) == []  # duplicate
    r.observe_server_seq(6)  # heartbeat: 4..6 exist but never came
    assert r.needs_resync
    assert [d["seq"] for d in r.load_snapshot(server.snapshot())] == []
    assert r.seq == 6 and not r.needs_resync
    assert sorted(n.name for n in r.graph.nodes()) == [f"n{i}" for i in range(6)]


def test_snapshot_then_newer_buffered_deltas():
    snap0, deltas, server = make_deltas(5)
    mid = ServerCore.from_snapshot(snap0)
    for d in deltas[:3]:
        mid.replay(d)
    r = Replica()
    for d in deltas:  # all arrive before the snapshot answer
        r.receive(d)
    assert [d["seq"] for d in r.load_snapshot(mid.snapshot())] == [4, 5]
    mine = dsr_json.to_json(r.graph, "snapshot", seq=r.seq)
    mine["claims"] = r.claims.to_json()
    assert json.dumps(mine, sort_keys=True) == json.dumps(server.snapshot(), sort_keys=True)


def test_store_journal_survives_and_torn_tail_is_dropped(tmp_path):
    snap0, deltas, server = make_deltas(4)
    store = StateStore(tmp_path)
    store.open()
    store.write_snapshot(snap0)
    for d in deltas:
        store.append(d)
    store.flush()
    with open(tmp_path / "journal.jsonl", "a") as f:
        f.write('{"seq": 5, "ops": [')  # a crash in the middle of a write
    store.close()

    again = StateStore(tmp_path)
    again.open()
    core = ServerCore.from_snapshot(again.load_snapshot())
    assert again.replay_journal(core.seq, core.replay) == 4
    assert core.seq == 4 and "torn" in again.warnings[0]
    assert json.dumps(core.snapshot(), sort_keys=True) == json.dumps(
        server.snapshot(), sort_keys=True
    )
    again.close()


def test_compaction_keeps_everything_and_skips_replayed_lines(tmp_path):
    snap0, deltas, server = make_deltas(4)
    store = StateStore(tmp_path, compact_every=2)
    store.open()
    store.write_snapshot(snap0)
    mirror = ServerCore.from_snapshot(snap0)
    for d in deltas:
        store.append(d)
        mirror.replay(d)
        if store.needs_compaction():
            store.write_snapshot(mirror.snapshot())
    store.flush()
    store.close()
    assert json.loads((tmp_path / "snapshot.json").read_text())["seq"] == 4
    assert (tmp_path / "journal.jsonl").read_text() == ""
    again = StateStore(tmp_path)
    again.open()
    core = ServerCore.from_snapshot(again.load_snapshot())
    again.replay_journal(core.seq, core.replay)
    assert core.seq == 4
    again.close()


def test_a_state_directory_has_one_server(tmp_path):
    a = StateStore(tmp_path)
    a.open()
    with pytest.raises(StateDirLocked, match="in use"):
        StateStore(tmp_path).open()
    a.close()


def test_a_damaged_journal_is_reported_not_skipped(tmp_path):
    snap0, deltas, _ = make_deltas(3)
    store = StateStore(tmp_path)
    store.open()
    store.write_snapshot(snap0)
    store.append(deltas[0])
    store.append(deltas[2])  # seq 2 missing
    store.close()
    again = StateStore(tmp_path)
    again.open()
    core = ServerCore.from_snapshot(again.load_snapshot())
    with pytest.raises(CorruptState, match="seq 3"):
        again.replay_journal(core.seq, core.replay)
    again.close()


def test_a_state_remembers_its_world_and_refuses_another(tmp_path):
    from dsr_graph.formats.state_store import origin_conflict, world_origin

    room, other = tmp_path / "room.json", tmp_path / "other.json"
    room.write_text('{"a": 1}')
    other.write_text('{"a": 2}')
    store = StateStore(tmp_path / "state")
    store.open()
    assert store.read_origin() is None  # a state from before origin.json: taken as it is
    store.write_origin(world_origin(str(room)))
    stored = store.read_origin()
    assert stored == {"world_file": str(room.resolve()), "sha256": stored["sha256"]}
    assert origin_conflict(stored, world_origin(str(room)), 7) is None  # a restart
    moved = tmp_path / "moved.json"
    moved.write_bytes(room.read_bytes())
    assert origin_conflict(stored, world_origin(str(moved)), 7) is None  # same content
    assert origin_conflict(stored, world_origin(""), 7) is None  # no world asked for
    conflict = origin_conflict(stored, world_origin(str(other)), 7)
    assert str(room.resolve()) in conflict and str(other.resolve()) in conflict
    assert "seq 7" in conflict
    empty = {"world_file": "", "sha256": ""}
    assert "an empty graph" in origin_conflict(empty, world_origin(str(room)), 0)
    store.close()
