"""Transactions: ordered ops, all or nothing, preconditions as compare-and-set, precise reasons,
and canonical ops that replay to the same graph."""

import copy
import json

import pytest

from dsr_graph.exceptions import TransactionRejected
from dsr_graph.formats import dsr_json
from dsr_graph.model.graph import Graph
from dsr_graph.model.transaction import apply_ops, apply_transaction, parse_transaction

from invariants import assert_invariants

IDENTITY = [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]


def state(graph):
    return json.dumps(dsr_json.to_json(graph, "snapshot"), sort_keys=True)


@pytest.fixture
def g():
    graph = Graph()
    apply_ops(
        graph,
        [
            {"op": "insert_node", "name": "room", "type": "room"},
            {"op": "insert_node", "name": "robot", "type": "robot"},
            {"op": "insert_node", "name": "speaking", "type": "state"},
            {"op": "insert_node", "name": "test", "type": "test"},
            {"op": "insert_node", "name": "test_part", "type": "test_part"},
            {
                "op": "insert_edge",
                "from": "room",
                "to": "robot",
                "type": "RT",
                "rt": {"translation": [0, 0, 0], "rotation_euler_xyz": [0, 0, 0]},
            },
            {"op": "insert_edge", "from": "robot", "to": "speaking", "type": "is_not"},
            {
                "op": "insert_edge",
                "from": "test",
                "to": "test_part",
                "type": "is_in",
                "attrs": {"text": "xxx"},
            },
        ],
    )
    return graph


def rejected(graph, doc):
    before = state(graph)
    with pytest.raises(TransactionRejected) as info:
        apply_transaction(graph, doc)
    assert state(graph) == before, "a rejected transaction must leave the graph exactly as it was"
    return info.value.violation


def test_speech_rule_as_one_compare_and_set(g):
    """Paper, Fig. 3 / Algorithm 3: robot is_not speaking -> robot is speaking, atomically."""
    tx = {
        "agent": "speech",
        "preconditions": [
            {"check": "edge_exists", "from": "robot", "to": "speaking", "type": "is_not"},
            {
                "check": "attr_equals",
                "from": "test",
                "to": "test_part",
                "type": "is_in",
                "attr": "text",
                "value": "xxx",
            },
        ],
        "ops": [
            {"op": "delete_edge", "from": "robot", "to": "speaking", "type": "is_not"},
            {"op": "insert_edge", "from": "robot", "to": "speaking", "type": "is"},
        ],
    }
    _, canonical = apply_transaction(g, copy.deepcopy(tx))
    assert g.edge("robot", "speaking", "is") and not g.edge("robot", "speaking", "is_not")
    assert [op["op"] for op in canonical] == ["delete_edge", "insert_edge"]
    # The same rule a second time (another agent racing) fails its precondition and changes nothing.
    v = rejected(g, tx)
    assert v.rule == "precondition" and v.at == "precondition 0 (edge_exists)"
    assert "'robot'->'speaking' (is_not)" in v.element


def test_a_failing_op_rolls_back_every_earlier_op(g):
    v = rejected(
        g,
        {
            "ops": [
                {"op": "set_node_attrs", "node": "robot", "attrs": {"level": 1}},
                {"op": "delete_edge", "from": "robot", "to": "speaking", "type": "is_not"},
                {"op": "insert_node", "name": "person", "type": "person"},
                {
                    "op": "insert_edge",
                    "from": "robot",
                    "to": "person",
                    "type": "RT",
                    "rt": {"matrix": [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]},
                },
                {"op": "delete_node", "node": "test"},
                {"op": "insert_edge", "from": "person", "to": "person", "type": "is_with"},
            ]
        },
    )
    assert (
        v.rule == "no-self-loop"
        and v.at == "op 5 (insert_edge)"
        and v.element == "edge 'person'->'person' (is_with)"
    )
    assert g.node("robot").version == 1 and "person" not in g and "test" in g
    assert g.edge("test", "test_part", "is_in").attrs == {"text": "xxx"}
    assert_invariants(g)


def test_reason_names_op_element_and_rule(g):
    v = rejected(
        g, {"ops": [{"op": "insert_edge", "from": "robot", "to": "ghost", "type": "is_with"}]}
    )
    assert (
        str(v) == "op 0 (insert_edge): edge 'robot'->'ghost' (is_with): node-missing: "
        "node 'ghost' does not exist"
    )


def test_end_of_transaction_rules(g):
    v = rejected(
        g,
        {
            "ops": [
                {"op": "insert_node", "name": "a", "type": "transform"},
                {"op": "insert_node", "name": "b", "type": "transform"},
                {
                    "op": "insert_edge",
                    "from": "a",
                    "to": "b",
                    "type": "RT",
                    "rt": {"matrix": IDENTITY},
                },
            ]
        },
    )
    assert v.rule == "rt-single-tree" and v.at == "end of transaction"
    # Re-rooting in one transaction is fine: the intermediate forest is never visible.
    apply_ops(
        g,
        [
            {"op": "insert_node", "name": "a", "type": "transform"},
            {
                "op": "insert_edge",
                "from": "a",
                "to": "room",
                "type": "RT",
                "rt": {"matrix": IDENTITY},
            },
        ],
    )
    assert g.rt_root().name == "a"
    assert_invariants(g)


@pytest.mark.parametrize(
    "check, rule_text",
    [
        ({"check": "node_exists", "node": "ghost"}, "expected to exist"),
        ({"check": "node_absent", "node": "robot"}, "expected not to exist"),
        (
            {"check": "edge_absent", "from": "robot", "to": "speaking", "type": "is_not"},
            "expected not to exist",
        ),
        ({"check": "attr_equals", "node": "robot", "attr": "level", "value": 1}, "found absent"),
        (
            {
                "check": "attr_equals",
                "from": "test",
                "to": "test_part",
                "type": "is_in",
                "attr": "text",
                "value": "yyy",
            },
            "found 'xxx'",
        ),
        ({"check": "version_equals", "node": "robot", "version": 7}, "found 1"),
        (
            {"check": "version_equals", "from": "robot", "to": "room", "type": "RT", "version": 1},
            "does not exist",
        ),
    ],
)
def test_each_precondition_kind(g, check, rule_text):
    v = rejected(
        g,
        {
            "preconditions": [check],
            "ops": [{"op": "set_node_attrs", "node": "robot", "attrs": {"level": 2}}],
        },
    )
    assert v.rule == "precondition" and rule_text in v.message


def test_version_precondition_is_compare_and_set(g):
    apply_transaction(
        g,
        {
            "preconditions": [{"check": "version_equals", "node": "robot", "version": 1}],
            "ops": [{"op": "set_node_attrs", "node": "robot", "attrs": {"level": 2}}],
        },
    )
    assert g.node("robot").version == 2


@pytest.mark.parametrize(
    "doc, fragment",
    [
        ([], "must be a JSON object"),
        ({"ops": []}, "non-empty list"),
        ({"ops": [{"op": "explode"}]}, "unknown op 'explode'"),
        ({"ops": [{"op": ["x"]}]}, "unknown op"),
        ({"ops": [{"op": "insert_node", "name": "x"}]}, "needs type"),
        (
            {"ops": [{"op": "insert_node", "name": "x", "type": "robot", "colour": 1}]},
            "does not take colour",
        ),
        (
            {"ops": [{"op": "insert_node", "name": ["x"], "type": "robot"}]},
            '"name" must be a string',
        ),
        ({"ops": [{"op": "delete_node", "node": 1.5}]}, "node name (string) or id (integer)"),
        ({"ops": [{"op": "delete_node", "node": "robot"}], "version": 2}, "not supported"),
        ({"ops": [{"op": "delete_node", "node": "robot"}], "sneaky": 1}, "unknown keys"),
        (
            {
                "ops": [{"op": "delete_node", "node": "robot"}],
                "preconditions": [{"check": "maybe"}],
            },
            "unknown check",
        ),
        (
            {
                "ops": [{"op": "delete_node", "node": "robot"}],
                "preconditions": [{"check": "attr_equals", "attr": "a", "value": 1}],
            },
            "either a node",
        ),
        ({"ops": [{"op": "set_node_attrs", "node": "robot", "attrs": [1]}]}, "must be an object"),
    ],
)
def test_malformed_requests_are_rejected_with_the_reason(g, doc, fragment):
    v = rejected(g, doc)
    assert fragment in str(v)


def test_canonical_ops_replay_to_an_equal_graph(g):
    replica = Graph()
    replica_ops = []
    primary = Graph()
    docs = [
        {
            "ops": [
                {"op": "insert_node", "name": "room", "type": "room"},
                {"op": "insert_node", "name": "person", "type": "person", "attrs": {"pos_x": 3}},
            ]
        },
        {
            "ops": [
                {
                    "op": "insert_edge",
                    "from": "room",
                    "to": "person",
                    "type": "RT",
                    "rt": {"translation": [1, 2, 3], "quaternion_wxyz": [0, 0, 0, 1]},
                }
            ]
        },
        {
            "ops": [
                {
                    "op": "set_rt",
                    "from": "room",
                    "to": "person",
                    "rt": {"translation": [1, 2, 4], "rotation_euler_xyz": [0.1, 0.2, 0.3]},
                },
                {"op": "set_node_attrs", "node": 2, "attrs": {"level": 4}},
            ]
        },
    ]
    for doc in docs:
        _, canonical = apply_transaction(primary, doc)
        replica_ops.append(json.loads(json.dumps(canonical)))  # through the wire
    for ops in replica_ops:
        apply_ops(replica, ops)
    assert state(replica) == state(primary)
    # canonical ops name nodes, carry assigned ids and exact matrices
    assert replica_ops[0][1]["id"] == 2 and replica_ops[2][1]["node"] == "person"
    assert replica_ops[0][1]["attrs"] == {"pos_x": 3.0}


def test_parse_keeps_the_request_metadata():
    tx = parse_transaction(
        {"id": "t1", "agent": "pelea", "priority": 5, "ops": [{"op": "delete_node", "node": 1}]}
    )
    assert (tx.id, tx.agent, tx.priority) == ("t1", "pelea", 5)
    assert tx.to_json()["kind"] == "transaction"
