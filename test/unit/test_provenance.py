"""Provenance: every attribute the server accepts carries the time and the agent of its last
write, the same on the server, on every replica, after a restart and in every document."""

import json

import pytest

from dsr_graph.exceptions import FormatError
from dsr_graph.formats import dsr_json
from dsr_graph.formats.state_store import StateStore
from dsr_graph.model import provenance
from dsr_graph.model.graph import Graph
from dsr_graph.protocol.replica import Replica
from dsr_graph.protocol.server_core import Rejection, ServerCore

RT = {"translation": [1.0, 0.0, 0.0], "rotation_euler_xyz": [0.0, 0.0, 0.0]}


def tx(agent, *ops):
    return json.dumps({"agent": agent, "ops": list(ops)})


def scene():
    """A server that saw three agents write: (core, deltas)."""
    core = ServerCore(Graph())
    deltas = [
        core.submit(
            tx(
                "/setup",
                {"op": "insert_node", "name": "room", "type": "room", "attrs": {"color": "w"}},
                {"op": "insert_node", "name": "p", "type": "cup", "attrs": {"name": "Ann"}},
                {"op": "insert_edge", "from": "room", "to": "p", "type": "RT", "rt": RT},
            ),
            now=100.0,
        ),
        core.submit(
            tx("/speech", {"op": "set_node_attrs", "node": "p", "attrs": {"color": "red"}}),
            now=200.0,
        ),
        core.submit(tx("/arm", {"op": "set_rt", "from": "room", "to": "p", "rt": RT}), now=300.0),
        core.submit(
            tx("/panel", {"op": "remove_node_attrs", "node": "room", "names": ["color"]}),
            now=400.0,
        ),
    ]
    assert not any(isinstance(d, Rejection) for d in deltas)
    return core, deltas


def test_each_attribute_carries_the_time_and_agent_of_its_last_write():
    core, _ = scene()
    p = core.graph.node("p")
    assert p.prov == {"name": (100.0, "/setup"), "color": (200.0, "/speech")}
    assert core.graph.node("room").prov == {}  # its only attribute was removed
    assert core.graph.edge("room", "p", "RT").prov == {provenance.RT_KEY: (300.0, "/arm")}


def test_a_refused_write_stamps_nothing():
    core, _ = scene()
    refused = core.submit(
        tx(
            "/intruder",
            {"op": "set_node_attrs", "node": "p", "attrs": {"color": "blue"}},
            {"op": "delete_node", "node": "ghost"},
        ),
        now=500.0,
    )
    assert isinstance(refused, Rejection)
    assert core.graph.node("p").prov["color"] == (200.0, "/speech")


def test_replicas_and_a_replayed_journal_stamp_the_same_without_more_on_the_wire():
    core, deltas = scene()
    wire = {"seq", "stamp", "agent", "id", "ops", "claims", "volatile"}
    assert all(set(d) <= wire for d in deltas)
    replica = Replica()
    replica.load_snapshot(ServerCore(Graph()).snapshot())
    for delta in deltas:
        replica.receive(json.loads(json.dumps(delta)))
    replayed = ServerCore(Graph())
    for delta in deltas:
        replayed.replay(json.loads(json.dumps(delta)))
    for graph in (replica.graph, replayed.graph):
        assert graph.node("p").prov == core.graph.node("p").prov
        assert graph.edge("room", "p", "RT").prov == core.graph.edge("room", "p", "RT").prov


def test_snapshots_carry_provenance_and_a_late_joiner_has_it(tmp_path):
    core, deltas = scene()
    snap = json.loads(json.dumps(core.snapshot()))
    person = next(n for n in snap["nodes"] if n["name"] == "p")
    assert person["provenance"] == {"name": [100.0, "/setup"], "color": [200.0, "/speech"]}
    late = Replica()
    late.load_snapshot(snap)
    assert late.graph.node("p").prov == core.graph.node("p").prov
    checked, _ = dsr_json.snapshot_from_json(snap)  # the checked path reads them too
    assert checked.node("p").prov == core.graph.node("p").prov
    # the server's own store: a restart from its snapshot and journal keeps every stamp
    store = StateStore(tmp_path)
    store.open()
    store.write_snapshot(ServerCore(Graph()).durable_snapshot())
    for delta in deltas:
        store.append(delta)
    store.flush()
    store.close()
    again = StateStore(tmp_path)
    again.open()
    restored, _, _ = ServerCore.restore(again.load_snapshot(), again.replay_journal)
    again.close()
    assert restored.graph.node("p").prov == core.graph.node("p").prov


def test_a_world_file_may_carry_provenance_or_not():
    core, _ = scene()
    doc = json.loads(json.dumps(dsr_json.to_json(core.graph, "world")))
    graph, violations = dsr_json.from_json(doc)
    assert not violations and graph.node("p").prov == core.graph.node("p").prov
    for item in doc["nodes"] + doc["edges"]:
        item.pop("provenance", None)
    graph, violations = dsr_json.from_json(doc)
    assert not violations and graph.node("p").prov == {}


@pytest.mark.parametrize(
    "bad, says",
    [
        ({"color": [1.0]}, "must be [time, agent]"),
        ({"color": ["1", "/a"]}, "must be [time, agent]"),
        ({"color": [1.0, 7]}, "must be [time, agent]"),
        ({"height": [1.0, "/a"]}, "which it does not have"),
        (["color"], "must be an object"),
    ],
)
def test_bad_provenance_in_a_file_is_reported_by_name_and_left_out(bad, says):
    doc = {
        "format": "dsr-graph",
        "version": 1,
        "kind": "world",
        "units": {"length": "m"},
        "nodes": [{"name": "p", "type": "person", "attrs": {"color": "red"}, "provenance": bad}],
        "edges": [],
    }
    graph, violations = dsr_json.from_json(doc)
    assert graph.node("p").attrs == {"color": "red"} and graph.node("p").prov == {}
    assert len(violations) == 1 and says in str(violations[0]) and "'p'" in str(violations[0])
    with pytest.raises(FormatError, match="provenance"):
        dsr_json.snapshot_from_json(dict(doc, kind="snapshot", seq=0))


def test_shown_for_people():
    core, _ = scene()
    assert provenance.shown(core.graph.node("p").prov) == {
        "color": {"time": 200.0, "agent": "/speech"},
        "name": {"time": 100.0, "agent": "/setup"},
    }
