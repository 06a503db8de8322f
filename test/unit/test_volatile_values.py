"""Volatile values (sensor data): declared in the vocabulary, numbered after the durable change they
follow, applied by a replica at exactly that seq and skipped otherwise, never journalled; a
change that touches anything else stays durable, and a journal replays whatever volatile values
a crash lost."""

import json

import pytest

from dsr_graph.exceptions import VocabularyError
from dsr_graph.formats.state_store import StateStore
from dsr_graph.model.graph import Graph
from dsr_graph.model.vocabulary import Vocabulary
from dsr_graph.protocol.history import History
from dsr_graph.protocol.local_bus import LocalBus
from dsr_graph.protocol.replica import Replica
from dsr_graph.protocol.server_core import Rejection, ServerCore
from dsr_graph.protocol.volatility import follows, is_volatile

VOCABULARY = {
    "format": "dsr-vocabulary",
    "version": 1,
    "node_types": {
        "thing": "a symbol",
        "sensor": {"doc": "moves with the world", "volatile_pose": True},
    },
    "edge_types": {"has": "has"},
    "attributes": {
        "reading": {"type": "float_vector", "volatile": True},
        "stamp": {"type": "float", "volatile": True, "doc": "when"},
        "label": "string",
    },
}


POSE = {"translation": [0.0, 0, 0], "rotation_euler_xyz": [0, 0, 0]}


def world() -> ServerCore:
    graph = Graph(Vocabulary.from_json(VOCABULARY))
    core = ServerCore(graph)
    ops = [
        {"op": "insert_node", "name": "room", "type": "thing"},
        {"op": "insert_node", "name": "cam", "type": "sensor"},
        {"op": "insert_edge", "from": "room", "to": "cam", "type": "RT", "rt": POSE},
    ]
    assert not isinstance(core.submit(json.dumps({"ops": ops})), Rejection)
    return core


def submit(core: ServerCore, *ops, **extra):
    result = core.submit(json.dumps({"ops": list(ops), **extra}), now=1.0, sender="/a")
    assert not isinstance(result, Rejection), result
    return result


def reading(value: float, node: str = "cam"):
    return {"op": "set_node_attrs", "node": node, "attrs": {"reading": [value], "stamp": value}}


MOVE = {
    "op": "set_rt",
    "from": "room",
    "to": "cam",
    "rt": {"translation": [1.0, 0, 0], "rotation_euler_xyz": [0, 0, 0]},
}


def test_the_vocabulary_declares_volatile_values_and_keeps_them_through_json():
    vocabulary = Vocabulary.from_json(VOCABULARY)
    assert vocabulary.volatile == {"reading", "stamp"}
    assert vocabulary.volatile_poses == {"sensor"}
    again = Vocabulary.from_json(vocabulary.to_json())
    assert (again.volatile, again.volatile_poses) == (
        vocabulary.volatile,
        vocabulary.volatile_poses,
    )
    default = Vocabulary.default()
    assert {"skeleton_frames", "frame_time", "joint_confidence"} <= default.volatile
    assert {"person", "joint"} <= default.volatile_poses
    assert not {"posture", "tug_seconds", "phase_seconds", "band"} & default.volatile


@pytest.mark.parametrize(
    ("where", "spec", "named"),
    [
        ("attributes", {"x": {"type": "float", "volatile": "yes"}}, "volatile"),
        ("attributes", {"x": {"type": "float", "fast": True}}, "fast"),
        ("node_types", {"x": {"doc": "d", "volatile_pose": 1}}, "volatile_pose"),
        ("node_types", {"x": {"doc": "d", "often": True}}, "volatile_pose"),
    ],
)
def test_a_bad_volatile_declaration_is_refused_by_name(where, spec, named):
    doc = {**VOCABULARY, where: spec}
    with pytest.raises(VocabularyError, match=named):
        Vocabulary.from_json(doc)


def test_only_sensor_values_make_a_change_volatile():
    core = world()
    seq = core.seq
    first = submit(core, reading(1.0), MOVE)
    second = submit(core, reading(2.0))
    assert is_volatile(first) and is_volatile(second)
    assert first["seq"] == second["seq"] == seq and second["volatile"] == first["volatile"] + 1
    assert core.seq == seq  # no seq of their own
    durable = [
        [reading(3.0), {"op": "set_node_attrs", "node": "cam", "attrs": {"label": "x"}}],
        [{"op": "remove_node_attrs", "node": "cam", "names": ["reading"]}],
        [{"op": "insert_node", "name": "other", "type": "sensor"}],
        [
            {"op": "set_rt", "from": "room", "to": "cam", "rt": POSE},
            {"op": "insert_node", "name": "n", "type": "thing"},
        ],
    ]
    for ops in durable:
        delta = submit(core, *ops)
        assert not is_volatile(delta) and delta["seq"] == core.seq
    claim = submit(core, reading(4.0), claim=[{"node": "cam"}])
    assert not is_volatile(claim)  # a claim granted is a symbol


def test_the_pose_of_a_symbol_stays_durable():
    core = world()
    submit(core, {"op": "insert_node", "name": "table", "type": "thing"})
    submit(core, {"op": "insert_edge", "from": "room", "to": "table", "type": "RT", "rt": POSE})
    moved = submit(core, {"op": "set_rt", "from": "room", "to": "table", "rt": POSE})
    assert not is_volatile(moved)


def test_a_replica_applies_a_volatile_delta_only_at_its_seq():
    core = world()
    replica = Replica(core.graph.vocabulary)
    replica.load_snapshot(json.loads(json.dumps(core.snapshot())))  # as the wire gives it
    v1 = submit(core, reading(1.0))
    assert replica.receive(v1) == [v1] and replica.applied == 1  # progress, seq unchanged
    assert replica.graph.node("cam").attrs["reading"] == [1.0]
    d = submit(core, {"op": "set_node_attrs", "node": "cam", "attrs": {"label": "x"}})
    v2 = submit(core, reading(2.0))
    assert follows(v2, d["seq"]) and not follows(v2, d["seq"] - 1)
    applied = replica.applied
    assert replica.receive(v2) == []  # behind: d never came; skipped, not kept
    assert replica.needs_resync and not replica.has_hole
    assert replica.applied == applied  # no progress: an agent stalled so fetches a snapshot
    assert replica.receive(d) == [d]  # the durable one applies; the skipped one is gone
    assert replica.graph.node("cam").attrs["reading"] == [1.0]
    v3 = submit(core, reading(3.0))
    assert replica.receive(v3) == [v3] and replica.graph.node("cam").attrs["reading"] == [3.0]
    assert replica.receive(v1) == []  # an old one from before d: not at its seq any more


def test_volatile_changes_are_not_journalled_and_a_crash_loses_only_them(tmp_path):
    core = world()
    store = StateStore(tmp_path)
    store.open()
    store.write_snapshot(core.durable_snapshot())
    for delta in (
        submit(core, reading(1.0)),
        submit(core, {"op": "set_node_attrs", "node": "cam", "attrs": {"label": "kept"}}),
        submit(core, reading(2.0), MOVE),
        # a symbol that removes a value only a volatile change had set
        submit(core, {"op": "remove_node_attrs", "node": "cam", "names": ["label", "reading"]}),
        submit(core, {"op": "set_node_attrs", "node": "cam", "attrs": {"label": "last"}}),
    ):
        if not is_volatile(delta):  # as the server node journals them
            store.append(delta)
    store.flush()
    store.close()
    lines = (tmp_path / "journal.jsonl").read_text().splitlines()
    assert len(lines) == 2 + 1 and not any('"volatile"' in line for line in lines)

    again = StateStore(tmp_path)
    again.open()
    restored, replayed, _ = ServerCore.restore(
        again.load_snapshot(), again.replay_journal, core.graph.vocabulary
    )
    assert replayed == 3 and restored.seq == core.seq
    cam = restored.graph.node("cam")
    assert cam.attrs == {"label": "last"}  # every symbol; the lost readings did not break it
    again.close()


def test_the_viewer_history_and_the_local_bus_take_volatile_deltas():
    core = world()
    history = History(core.graph.vocabulary)
    history.reset(core.snapshot())
    seq = history.seq
    history.add(submit(core, reading(5.0)))
    assert history.seq == seq and history.graph.node("cam").attrs["reading"] == [5.0]
    assert history.since(seq) == []  # no place in the timeline

    bus = LocalBus(Graph(Vocabulary.from_json(VOCABULARY)))
    writer, reader = bus.agent("/w"), bus.agent("/r")
    results = []
    writer.send({"ops": [{"op": "insert_node", "name": "cam", "type": "sensor"}]})
    bus.deliver()
    writer.send({"ops": [reading(7.0)]}, results.append)
    bus.deliver()
    assert results and results[0].accepted and is_volatile(results[0].delta)
    assert reader.graph.node("cam").attrs["reading"] == [7.0]
