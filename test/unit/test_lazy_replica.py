"""A replica restores a snapshot lazily (``Graph.restore(lazy=True)``): nothing is built until
used, and once used it is the graph an eager restore gives; a malformed snapshot is still refused
when it is loaded; the snapshot's JSON is read without the walk every other message gets. Each
in both layouts of dsr/get_snapshot: the document of FORMAT.md, and column by column (what
DsrAgent asks for: each element's fields past its identity parsed only when it is built)."""

import gc
import json
import math
import weakref

import numpy as np
import pytest

from dsr_graph.exceptions import FormatError, JsonRefused
from dsr_graph.formats import dsr_json
from dsr_graph.formats.safe_json import loads_object
from dsr_graph.model.graph import Graph
from dsr_graph.model.lazy_nodes import LazyNodes
from dsr_graph.model.trusted_loading import PendingIndex
from dsr_graph.protocol.replica import Replica
from dsr_graph.protocol.server_core import Rejection, ServerCore


def server(n=30):
    core = ServerCore(Graph())
    ops = [{"op": "insert_node", "name": "world", "type": "transform"}]
    for i in range(1, n):
        ops.append(
            {"op": "insert_node", "name": f"n{i}", "type": "transform", "attrs": {"level": i}}
        )
        parent = "world" if i < 3 else f"n{i // 3}"
        rt = {"translation": [0.1 * i, 0.0, 0.0], "rotation_euler_xyz": [0.0, 0.0, 0.01 * i]}
        ops.append({"op": "insert_edge", "from": parent, "to": f"n{i}", "type": "RT", "rt": rt})
    ops.append({"op": "insert_node", "name": "flag", "type": "state", "attrs": {"level": 7}})
    ops.append({"op": "insert_edge", "from": "flag", "to": "n5", "type": "has"})
    for doc in (
        {"ops": ops},
        {"ops": [{"op": "set_node_attrs", "node": "n4", "attrs": {"level": -1}}]},
    ):
        assert not isinstance(core.submit(json.dumps(doc), now=2.0, sender="/writer"), Rejection)
    return core


def wire(core, layout=""):
    """The snapshot as a joiner reads it off the wire, in ``layout`` ("" or "columns")."""
    doc = core.snapshot()
    if layout == dsr_json.COLUMNS:
        doc = dsr_json.to_columns(doc, json.dumps)
    return loads_object(json.dumps(doc), None, walk=False)


LAYOUTS = pytest.mark.parametrize("layout", ["", dsr_json.COLUMNS])


@LAYOUTS
def test_nothing_is_built_until_used_and_then_it_is_the_eager_graph(layout):
    core = server()
    replica = Replica()
    replica.load_snapshot(wire(core, layout))
    graph = replica.graph
    assert isinstance(graph._nodes, LazyNodes) and graph._nodes.built() == 0
    # the edges' indexes wait for an edge to be used
    assert isinstance(vars(graph)["_edges"], PendingIndex)
    assert len(graph) == 31 and "n7" in graph and 99 not in graph._nodes
    assert graph._nodes.built() == 1  # "n7" in graph finds (builds) that one node
    n4 = graph.node("n4")
    assert n4.attrs == {"level": -1} and n4.version == 2 and n4.prov["level"][1] == "/writer"
    assert graph.find("nobody") is None and graph._nodes.get(10**6) is None
    eager, _ = dsr_json.snapshot_from_json(wire(core), trusted=True)
    assert np.allclose(graph.transform("n3", "n28"), eager.transform("n3", "n28"))
    assert type(vars(graph)["_edges"]) is dict and graph.edge_count() == eager.edge_count() == 30
    assert type(graph) is Graph  # a plain graph all along
    assert [e.type for e in graph.out_edges("flag")] == ["has"]
    assert sorted(n.name for n in graph.nodes()) == sorted(n.name for n in eager.nodes())
    assert graph._nodes.built() == 31
    assert dsr_json.to_json(graph, "snapshot", seq=1) == dsr_json.to_json(eager, "snapshot", seq=1)


@LAYOUTS
def test_deltas_apply_to_a_lazy_replica_as_to_an_eager_one(layout):
    core = server()
    replica = Replica()
    replica.load_snapshot(wire(core, layout))
    ops = [
        {"op": "set_node_attrs", "node": "n9", "attrs": {"level": 99}},
        {"op": "delete_node", "node": "flag"},
        {"op": "insert_node", "name": "late", "type": "state"},
        {
            "op": "set_rt",
            "from": "n3",
            "to": "n9",
            "rt": {"translation": [1, 2, 3], "rotation_euler_xyz": [0, 0, 1]},
        },
    ]
    for op in ops:
        delta = core.submit(json.dumps({"ops": [op]}), now=3.0, sender="/writer")
        assert not isinstance(delta, Rejection), delta
        assert replica.receive(json.loads(json.dumps(delta))) != []
    assert replica.graph.node("n9").attrs["level"] == 99 and "flag" not in replica.graph
    assert replica.graph.node("late").id == core.graph.node("late").id
    assert np.allclose(replica.graph.transform("world", "n9"), core.graph.transform("world", "n9"))
    assert as_json(replica.graph) == as_json(core.graph)


def as_json(graph):
    return json.loads(json.dumps(dsr_json.to_json(graph, "snapshot", seq=0)))


@pytest.mark.parametrize(
    ("break_it", "fragment"),
    [
        (lambda doc: doc["edges"].append({"from": "n1", "to": "ghost", "type": "has"}), "ghost"),
        (lambda doc: doc["nodes"].append(dict(doc["nodes"][1], id=999)), "repeat"),
        (lambda doc: doc["nodes"].append({"id": 1000, "name": "typeless"}), "type"),
        (lambda doc: doc["nodes"].append({"id": "7", "name": "x", "type": "state"}), "integers"),
    ],
)
def test_a_malformed_snapshot_is_refused_when_loaded_and_the_replica_kept(break_it, fragment):
    replica = Replica()
    replica.load_snapshot(wire(server()))
    before = replica.graph
    doc = wire(server())
    break_it(doc)
    with pytest.raises(FormatError, match=fragment):
        replica.load_snapshot(doc)
    assert replica.graph is before and replica.graph.node("n3").attrs == {"level": 3}


def rest(item):
    return json.dumps({k: v for k, v in item.items() if k not in ("id", "name", "type")})


@pytest.mark.parametrize(
    ("break_it", "fragment"),
    [
        (lambda doc: doc["edges"]["to"].__setitem__(0, "ghost"), "ghost"),
        (lambda doc: doc["nodes"]["name"].__setitem__(2, doc["nodes"]["name"][1]), "repeat"),
        (lambda doc: doc["nodes"]["type"].pop(), "one length"),
        (lambda doc: doc["edges"].pop("rest"), "rest"),
        (lambda doc: doc["nodes"]["id"].__setitem__(0, "1"), "integers"),
        (lambda doc: doc["edges"]["type"].__setitem__(0, 5), "strings"),
        (lambda doc: doc["nodes"]["rest"].__setitem__(4, {"attrs": {}}), "JSON text"),
        (lambda doc: doc.__setitem__("nodes", [1, 2]), "nodes"),
        (lambda doc: doc.__setitem__("units", {"length": "mm"}), "metres"),
    ],
)
def test_a_malformed_columnar_snapshot_is_refused_when_loaded_and_the_replica_kept(
    break_it, fragment
):
    replica = Replica()
    replica.load_snapshot(wire(server(), dsr_json.COLUMNS))
    before = replica.graph
    doc = wire(server(), dsr_json.COLUMNS)
    break_it(doc)
    with pytest.raises(FormatError, match=fragment):
        replica.load_snapshot(doc)
    assert replica.graph is before and replica.graph.node("n3").attrs == {"level": 3}


def test_columns_hold_the_snapshot_whole_and_read_back_as_its_rows():
    snapshot = json.loads(json.dumps(server().snapshot()))
    columns = dsr_json.to_columns(snapshot, json.dumps)
    assert columns["layout"] == "columns" and columns["claims"] == snapshot["claims"]
    assert columns["nodes"]["name"][:2] == ["world", "n1"] and len(columns["edges"]["rest"]) == 30
    assert json.loads(columns["edges"]["rest"][0]).keys() == {
        "attrs",
        "rt",
        "version",
        "provenance",
    }
    assert dsr_json.rows_of_columns(json.loads(json.dumps(columns))) == snapshot
    # read without trust (as rows, every element checked) it is the same graph
    checked, _ = dsr_json.snapshot_from_json(json.loads(json.dumps(columns)))
    assert as_json(checked) == as_json(dsr_json.snapshot_from_json(snapshot)[0])
    for bad_rest, fragment in (("[1]", "object"), ("{", "rest"), (7, "object")):
        broken = json.loads(json.dumps(columns))
        broken["nodes"]["rest"][3] = bad_rest
        with pytest.raises(FormatError, match=fragment):
            dsr_json.snapshot_from_json(broken)


def test_a_snapshot_is_read_without_the_walk_but_within_orjsons_limits():
    deep = '{"a": ' + "[" * 100 + "]" * 100 + "}"
    with pytest.raises(JsonRefused, match="deeper"):
        loads_object(deep)
    assert loads_object(deep, walk=False)["a"]  # a snapshot is not walked
    assert loads_object('{"a": 18446744073709551615}', walk=False)["a"] == 2**64 - 1
    for hostile in ('{"a": NaN}', '{"a": 1e400}', "[" * 2000 + "]" * 2000):
        with pytest.raises(JsonRefused):
            loads_object(hostile, walk=False)
    assert math.isclose(loads_object('{"a": 1e30}', walk=False)["a"], 1e30)


def test_lazy_nodes_behave_as_the_dict_they_stand_for():
    built = []
    nodes = LazyNodes(
        {1: "one", 2: "two", 3: "three"}, lambda raw: built.append(raw) or raw.upper()
    )
    assert len(nodes) == 3 and 2 in nodes and 4 not in nodes and built == []
    assert nodes[2] == "TWO" and nodes.get(2) == "TWO" and built == ["two"]
    assert nodes.get(4) is None and nodes.get(4, "none") == "none"
    with pytest.raises(KeyError):
        nodes[4]
    del nodes[1]  # never built
    del nodes[2]  # built
    assert len(nodes) == 1 and 1 not in nodes and built == ["two"]
    nodes[5] = "FIVE"
    assert sorted(nodes) == [3, 5] and sorted(nodes.values()) == ["FIVE", "THREE"]
    assert max(nodes) == 5 and len(nodes) == 2 and nodes.built() == 2


@LAYOUTS
def test_a_replaced_replica_graph_is_freed_without_the_collector(layout):
    """The agent moves a loaded snapshot out of the collector's reach (collector.settle): its
    graph must hold no reference cycle, or a resync would leak the old one (the default
    vocabulary declares binary attributes: the decoder a lazy graph keeps is built)."""
    core = server()
    replica = Replica()
    gc.disable()
    try:
        replica.load_snapshot(wire(core, layout))
        replica.graph.node("n3")
        replica.graph.transform("world", "n9")
        old = weakref.ref(replica.graph)
        replica.load_snapshot(wire(core, layout))
        assert old() is None
    finally:
        gc.enable()
