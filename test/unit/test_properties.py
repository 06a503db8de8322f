"""Property-based tests of the graph model (hypothesis).

- Mostly-valid transactions drawn against the graph as it grows (test/transaction_generator.py):
  every invariant holds after each one, a rejected one changes nothing, a replica replaying the
  accepted deltas ends equal, and at least MIN_ACCEPTED of them are accepted, so the test cannot
  silently stop exercising the model.
- Hostile transactions (wrong names, types and matrices almost everywhere): the same guarantees
  on the rejection paths.
"""

import json

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st
from transaction_generator import HypothesisPick, RandomPick, TransactionGenerator, rt_depth

from dsr_graph.exceptions import TransactionRejected
from dsr_graph.formats import dsr_json
from dsr_graph.model.graph import Graph
from dsr_graph.model.transaction import apply_ops, apply_transaction

from invariants import assert_invariants

MISTAKE_EVERY = 8  # one transaction in eight carries a deliberate mistake
MIN_ACCEPTED = 0.85  # so at least this share must be accepted (7/8 of them, exactly)

NAMES = [f"n{i}" for i in range(6)]
node_ref = st.one_of(st.sampled_from(NAMES), st.integers(1, 8))
edge_type = st.sampled_from(["RT", "is", "is_with", "has", "bogus"])
rt = st.one_of(
    st.builds(
        lambda t, e: {"translation": t, "rotation_euler_xyz": e},
        st.lists(st.floats(-10, 10), min_size=3, max_size=3),
        st.lists(st.floats(-3, 3), min_size=3, max_size=3),
    ),
    st.just({"matrix": [[2, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]}),  # not rigid
)
attrs = st.dictionaries(
    st.sampled_from(["level", "text", "pos_x", "nonsense"]),
    st.one_of(st.integers(-3, 3), st.text(max_size=3), st.floats(-1, 1)),
    max_size=2,
)

op = st.one_of(
    st.builds(
        lambda n, t, a: {"op": "insert_node", "name": n, "type": t, "attrs": a},
        st.sampled_from(NAMES),
        st.sampled_from(["transform", "robot", "alien"]),
        attrs,
    ),
    st.builds(lambda n: {"op": "delete_node", "node": n}, node_ref),
    st.builds(lambda n, a: {"op": "set_node_attrs", "node": n, "attrs": a}, node_ref, attrs),
    st.builds(lambda n: {"op": "remove_node_attrs", "node": n, "names": ["level"]}, node_ref),
    st.builds(
        lambda a, b, t, r: {
            "op": "insert_edge",
            "from": a,
            "to": b,
            "type": t,
            **({"rt": r} if t == "RT" else {}),
        },
        node_ref,
        node_ref,
        edge_type,
        rt,
    ),
    st.builds(
        lambda a, b, t: {"op": "delete_edge", "from": a, "to": b, "type": t},
        node_ref,
        node_ref,
        edge_type,
    ),
    st.builds(
        lambda a, b, r: {"op": "set_rt", "from": a, "to": b, "rt": r}, node_ref, node_ref, rt
    ),
    st.builds(
        lambda a, b, x: {"op": "set_edge_attrs", "from": a, "to": b, "type": "is", "attrs": x},
        node_ref,
        node_ref,
        attrs,
    ),
)
precondition = st.one_of(
    st.builds(lambda n: {"check": "node_exists", "node": n}, node_ref),
    st.builds(
        lambda a, b: {"check": "edge_absent", "from": a, "to": b, "type": "is"}, node_ref, node_ref
    ),
    st.builds(
        lambda n, v: {"check": "version_equals", "node": n, "version": v},
        node_ref,
        st.integers(1, 3),
    ),
)
transaction = st.builds(
    lambda ops, pre: {"ops": ops, "preconditions": pre},
    st.lists(op, min_size=1, max_size=4),
    st.lists(precondition, max_size=1),
)


def snapshot(graph):
    return json.dumps(dsr_json.to_json(graph, "snapshot"), sort_keys=True)


def grow(pick, steps):
    """Apply ``steps`` generated transactions to a new graph, one in MISTAKE_EVERY carrying a
    deliberate mistake, checking after each: the valid ones are accepted and the wrong ones
    rejected with a reason and no change, every invariant holds, and a replica replaying the
    accepted deltas stays equal. The graph and how many were accepted."""
    g, replica = Graph(), Graph()
    generator = TransactionGenerator(pick, g)
    accepted = 0
    for i in range(steps):
        mistake = i % MISTAKE_EVERY == MISTAKE_EVERY - 1
        doc = generator.transaction(g, mistake=mistake)
        before = snapshot(g)
        try:
            _, canonical = apply_transaction(g, doc)
        except TransactionRejected as e:
            assert mistake, f"a valid transaction was rejected: {e}\n{doc}"
            assert snapshot(g) == before, f"rejected ({e}) but the graph changed"
            assert e.violation.rule and e.violation.element and e.violation.message
        else:
            assert not mistake, f"a transaction with a mistake was accepted: {doc}"
            accepted += 1
            apply_ops(replica, json.loads(json.dumps(canonical)))
        assert_invariants(g)
    assert snapshot(replica) == snapshot(g)
    return g, accepted


@settings(max_examples=30, deadline=None)
@given(st.data())
def test_mostly_valid_transactions_keep_every_invariant(data):
    steps = data.draw(st.integers(16, 120))
    graph, accepted = grow(HypothesisPick(data), steps)
    assert accepted / steps >= MIN_ACCEPTED, f"only {accepted} of {steps} accepted"
    if graph.rt_root() is not None:  # kinematic chains agree with an independent composition
        names = [n.name for n in graph.nodes() if graph.is_geometric(n.id)]
        a, b = data.draw(st.sampled_from(names)), data.draw(st.sampled_from(names))
        assert np.allclose(
            graph.transform(a, b),
            np.linalg.inv(pose_from_root(graph, a)) @ pose_from_root(graph, b),
            atol=1e-6,
        )


def test_the_generator_reaches_large_deep_graphs():
    """Seeded, so its figures are the same on every run: hundreds of edges, a deep RT tree."""
    graph, accepted = grow(RandomPick(seed=2026), 600)
    print(
        f"accepted {accepted}/600, {len(graph)} nodes, {graph.edge_count()} edges, "
        f"RT depth {rt_depth(graph)}"
    )
    assert accepted / 600 >= MIN_ACCEPTED
    assert graph.edge_count() >= 250 and rt_depth(graph) >= 10


def pose_from_root(graph, name):
    pose = np.eye(4)
    node = graph.node(name)
    while graph.rt_parent(node.id) is not None:
        parent = graph.rt_parent(node.id)
        pose = graph.edge(parent.id, node.id, "RT").rt @ pose
        node = parent
    return pose


@settings(max_examples=200, deadline=None)
@given(st.lists(transaction, min_size=1, max_size=25))
def test_hostile_transactions_keep_every_invariant(transactions):
    g = Graph()
    replica = Graph()
    accepted = 0
    for doc in transactions:
        before = snapshot(g)
        try:
            _, canonical = apply_transaction(g, doc)
        except TransactionRejected as e:
            assert snapshot(g) == before, f"rejected ({e}) but the graph changed"
            assert e.violation.rule and e.violation.element and e.violation.message
        else:
            accepted += 1
            apply_ops(replica, json.loads(json.dumps(canonical)))  # a replica replays the delta
        assert_invariants(g)
    assert snapshot(replica) == snapshot(g)


@settings(max_examples=50, deadline=None)
@given(st.lists(transaction, min_size=1, max_size=15))
def test_snapshots_round_trip(transactions):
    g = Graph()
    for doc in transactions:
        try:
            apply_transaction(g, doc)
        except TransactionRejected:
            pass
    doc = json.loads(snapshot(g))
    restored, seq = dsr_json.snapshot_from_json(doc)
    assert snapshot(restored) == snapshot(g)
    trusted, _ = dsr_json.snapshot_from_json(
        json.loads(snapshot(g)), trusted=True
    )  # a replica's fast path
    assert snapshot(trusted) == snapshot(g)
    assert_invariants(trusted)
    if g.rt_root() is not None:  # its indexes work: the kinematic chain and the root
        assert trusted.rt_root().name == g.rt_root().name
