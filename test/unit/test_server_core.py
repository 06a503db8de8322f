"""The server's logic without ROS: sequencing, rejections of hostile input, claims, replay."""

import json

import pytest

from dsr_graph.model.graph import Graph
from dsr_graph.model.policy import AgentRule, Policy
from dsr_graph.model.transaction import apply_ops
from dsr_graph.protocol.server_core import Rejection, ServerCore

# claim priorities come from a policy only; these tests' agents, all free to write
PRIORITIES = Policy(
    [
        AgentRule(name, prio, frozenset("*"), frozenset("*"), frozenset("*"))
        for name, prio in [("/person", 2), ("/speech", 1), ("/panel", 2), ("/pelea", 5), ("*", 0)]
    ]
)


def core():
    g = Graph()
    apply_ops(
        g,
        [
            {"op": "insert_node", "name": "room", "type": "room"},
            {"op": "insert_node", "name": "robot", "type": "robot"},
            {"op": "insert_node", "name": "person", "type": "person"},
            {"op": "insert_node", "name": "speaking", "type": "state"},
            {
                "op": "insert_edge",
                "from": "room",
                "to": "person",
                "type": "RT",
                "rt": {"translation": [0, 0, 0], "rotation_euler_xyz": [0, 0, 0]},
            },
            {"op": "insert_edge", "from": "robot", "to": "speaking", "type": "is_not"},
        ],
    )
    return ServerCore(g, max_request_bytes=10_000, policy=PRIORITIES)


def submit(c, doc, now=100.0):
    return c.submit(json.dumps(doc), now=now)


def test_accepted_transactions_get_consecutive_seqs():
    c = core()
    d1 = submit(
        c,
        {
            "id": "a",
            "agent": "/x",
            "ops": [{"op": "set_node_attrs", "node": "robot", "attrs": {"level": 1}}],
        },
    )
    d2 = submit(c, {"ops": [{"op": "set_node_attrs", "node": "robot", "attrs": {"level": 2}}]})
    assert (d1["seq"], d2["seq"], c.seq) == (1, 2, 2)
    assert d1["id"] == "a" and d1["agent"] == "/x" and d1["stamp"] == 100.0
    assert d1["ops"] == [{"op": "set_node_attrs", "node": "robot", "attrs": {"level": 1}}]


@pytest.mark.parametrize(
    "text, rule, fragment",
    [
        ("{not json", "malformed", "not JSON"),
        ("[1, 2]", "malformed", "must be a JSON object"),
        ('{"ops": [{"op": "fly"}]}', "malformed", "unknown op 'fly'"),
        (
            '{"ops": [{"op": "delete_node", "node": {"a": 1}}]}',
            "malformed",
            "node name (string) or id",
        ),
        ("[" * 100_000 + "]" * 100_000, "too-large", "exceeds"),
        ("[" * 5000 + "]" * 5000, "malformed", ""),
        (
            '{"ops": [{"op": "delete_node", "node": "ghost"}], "id": "r1", "agent": "/y"}',
            "node-missing",
            "'ghost'",
        ),
    ],
)
def test_hostile_requests_are_rejected_and_change_nothing(text, rule, fragment):
    c = core()
    before = json.dumps(c.snapshot(), sort_keys=True)
    result = c.submit(text, now=1.0)
    assert isinstance(result, Rejection)
    assert result.violation.rule == rule and fragment in str(result.violation)
    assert json.dumps(c.snapshot(), sort_keys=True) == before and c.seq == 0


def test_rejection_carries_the_request_id_and_agent():
    r = core().submit(
        '{"id": "r1", "agent": "/y", "ops": [{"op": "delete_node", "node": "ghost"}]}'
    )
    assert r.to_json()["id"] == "r1" and r.to_json()["agent"] == "/y"
    assert (
        r.to_json()["error"]
        == "op 0 (delete_node): node 'ghost': node-missing: node 'ghost' does not exist"
    )


def test_claims_block_lower_and_equal_priorities_and_yield_to_higher():
    c = core()
    d = submit(c, {"agent": "/person", "claim": [{"node": "person"}]})
    assert d["claims"]["granted"][0]["target"] == {"node": "person"}
    write = {"op": "set_node_attrs", "node": "person", "attrs": {"level": 1}}
    for agent in ["/speech", "/panel"]:  # priorities 1 and 2 (PRIORITIES)
        r = submit(c, {"agent": agent, "ops": [write]})
        assert isinstance(r, Rejection) and r.violation.rule == "claimed"
        assert "claimed by '/person' with priority 2" in r.violation.message
    # moving the person (its RT edge) is protected too
    r = submit(
        c,
        {
            "agent": "/speech",
            "ops": [
                {
                    "op": "set_rt",
                    "from": "room",
                    "to": "person",
                    "rt": {"translation": [1, 0, 0], "rotation_euler_xyz": [0, 0, 0]},
                }
            ],
        },
    )
    assert isinstance(r, Rejection) and r.violation.rule == "claimed"
    # the holder itself writes freely
    assert not isinstance(submit(c, {"agent": "/person", "ops": [write]}), Rejection)
    # a higher priority goes through and preempts; the holder learns it from the delta
    d = submit(c, {"agent": "/pelea", "ops": [write]})
    assert d["claims"]["released"] == [
        {"target": {"node": "person"}, "agent": "/person", "reason": "preempted", "by": "/pelea"}
    ]
    assert len(c.claims) == 0


def test_pair_claims_cover_every_edge_type_between_the_pair():
    c = core()
    submit(c, {"agent": "/speech", "claim": [{"from": "robot", "to": "speaking"}]})
    r = submit(
        c,
        {
            "agent": "/other",  # priority 0, below /speech's 1
            "ops": [{"op": "insert_edge", "from": "robot", "to": "speaking", "type": "is"}],
        },
    )
    assert isinstance(r, Rejection) and "edge 'robot'->'speaking' (is)" in r.violation.element
    d = submit(
        c,
        {
            "agent": "/speech",
            "release": "all",
            "ops": [{"op": "insert_edge", "from": "robot", "to": "speaking", "type": "is"}],
        },
    )
    assert d["claims"]["released"][0]["reason"] == "released"
    assert not isinstance(
        submit(
            c,
            {
                "agent": "/panel",
                "ops": [{"op": "delete_edge", "from": "robot", "to": "speaking", "type": "is"}],
            },
        ),
        Rejection,
    )


def test_claims_need_an_agent_and_existing_nodes():
    c = core()
    assert "claims need" in str(submit(c, {"claim": [{"node": "person"}]}).violation)
    assert submit(c, {"agent": "/a", "claim": [{"node": "ghost"}]}).violation.rule == "node-missing"
    assert submit(c, {"agent": "/a", "claim": [{"nod": "x"}]}).violation.rule == "malformed"


def test_leases_expire_and_deleted_nodes_free_their_claims():
    c = core()
    submit(c, {"agent": "/a", "lease": 5, "claim": [{"node": "person"}]}, now=10.0)
    assert c.claims.expired(14.0) == [] and len(c.claims.expired(15.0)) == 1
    d = c.end_claims(c.claims.expired(15.0), "expired", now=15.0)
    assert (
        d["agent"] == "dsr_server"
        and d["ops"] == []
        and d["claims"]["released"][0]["reason"] == "expired"
    )
    submit(c, {"agent": "/a", "claim": [{"node": "speaking"}]})
    d = submit(c, {"agent": "/a", "ops": [{"op": "delete_node", "node": "speaking"}]})
    assert d["claims"]["released"][0]["reason"] == "node-deleted" and len(c.claims) == 0


def test_replay_rebuilds_the_same_state_from_snapshot_and_deltas():
    c = core()
    start = c.snapshot()
    deltas = [
        submit(c, {"agent": "/a", "claim": [{"node": "person"}]}),
        submit(c, {"ops": [{"op": "insert_node", "name": "x", "type": "transform"}]}),
    ]
    again = ServerCore.from_snapshot(json.loads(json.dumps(start)))
    for d in deltas:
        again.replay(json.loads(json.dumps(d)))
    assert json.dumps(again.snapshot(), sort_keys=True) == json.dumps(c.snapshot(), sort_keys=True)
    with pytest.raises(ValueError, match="out of order"):
        again.replay(deltas[0])


def test_a_request_sent_again_is_answered_not_applied_twice():
    core = ServerCore(Graph())
    tx = json.dumps(
        {
            "id": "a:1",
            "agent": "/a",
            "ops": [{"op": "insert_node", "name": "x", "type": "transform"}],
        }
    )
    first = core.submit(tx)
    again = core.submit(tx)
    assert first["seq"] == 1 and core.seq == 1
    assert again.duplicate_of == 1 and again.violation.rule == "duplicate"
    assert again.to_json()["duplicate_of"] == 1


def insert(ident, name):
    op = {"op": "insert_node", "name": name, "type": "transform"}
    return json.dumps({"id": ident, "ops": [op]})


def test_a_restarted_server_still_knows_the_requests_it_accepted():
    core = ServerCore(Graph())
    texts = [insert(f"a:{i}", f"n{i}") for i in range(3)]
    deltas = [core.submit(t) for t in texts]
    snapshot = json.loads(json.dumps(core.durable_snapshot()))  # as written to disk after seq 3
    later = core.submit(insert("a:9", "m"))
    restarted = ServerCore.from_snapshot(snapshot)
    restarted.replay(json.loads(json.dumps(later)))  # the journal after the snapshot
    assert [restarted.submit(t).duplicate_of for t in texts] == [d["seq"] for d in deltas]
    assert restarted.submit(insert("a:9", "m")).duplicate_of == 4
    assert restarted.seq == 4


@pytest.mark.parametrize(
    ("doc", "limit"),
    [
        (
            {
                "ops": [
                    {"op": "set_node_attrs", "node": "robot", "attrs": {"n": i}} for i in range(4)
                ]
            },
            "max_ops (3)",
        ),
        (
            {"ops": [{"op": "insert_node", "name": f"n{i}", "type": "object"} for i in range(2)]},
            "max_nodes (5)",
        ),
        ({"claim": [{"node": "robot"}], "lease": 301}, "max_lease (300.0 s)"),
        (
            {"ops": [{"op": "set_node_attrs", "node": "robot", "attrs": {"t": "é" * 6000}}]},
            "max_request_bytes (10000)",
        ),
    ],
)
def test_server_limits_are_named_and_change_nothing(doc, limit):
    c = core()
    c.max_ops, c.max_nodes = 3, 5
    before = json.dumps(c.snapshot(), sort_keys=True)
    result = submit(c, {"agent": "/pelea", **doc})
    assert isinstance(result, Rejection), result
    assert limit in str(result.violation)
    assert json.dumps(c.snapshot(), sort_keys=True) == before and c.seq == 0


def test_an_infinite_lease_is_not_json_and_a_finite_one_within_the_limit_holds():
    c = core()
    text = '{"agent": "/pelea", "claim": [{"node": "robot"}], "lease": 1e309}'
    assert "infinity" in str(c.submit(text, now=1.0).violation)
    delta = submit(c, {"agent": "/pelea", "claim": [{"node": "robot"}], "lease": 300})
    assert delta["claims"]["granted"][0]["expires"] == 400.0
