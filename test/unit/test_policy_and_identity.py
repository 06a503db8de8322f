"""Who may write what (the policy) and who sent a request (identity from the ROS graph), as
pure logic: the server's checks without the middleware."""

import json
import re
from pathlib import Path

import pytest

from dsr_graph.exceptions import FormatError
from dsr_graph.model.graph import Graph
from dsr_graph.model.policy import OPEN, Policy
from dsr_graph.model.transaction import apply_ops
from dsr_graph.protocol.identity import Publisher, agent_topic, sender_on
from dsr_graph.protocol.server_core import Rejection, ServerCore

POLICY = {
    "version": 1,
    "agents": [
        {
            "name": "/pelea",
            "priority": 10,
            "nodes": ["test_item"],
            "edges": ["is_in", "is_not"],
            "attributes": ["text", "item"],
        },
        {"name": "/speech", "priority": 1, "edges": ["is", "is_not"]},
        {"name": "/clarc_*", "priority": 3, "attributes": ["item"]},
    ],
}


def graph():
    g = Graph()
    apply_ops(
        g,
        [
            {"op": "insert_node", "name": "robot", "type": "robot"},
            {"op": "insert_node", "name": "speaking", "type": "state"},
            {"op": "insert_node", "name": "test", "type": "test"},
            {"op": "insert_node", "name": "test_part", "type": "test_part"},
            {"op": "insert_edge", "from": "robot", "to": "speaking", "type": "is_not"},
        ],
    )
    return g


def send(core, agent, ops, **extra):
    doc = {"ops": ops, **extra} if ops else extra
    return core.submit(json.dumps(doc), now=1.0, sender=agent)


def snapshot_text(core):
    return json.dumps(core.snapshot(), sort_keys=True)


@pytest.mark.parametrize(
    ("agent", "op", "named"),
    [
        (
            "/speech",
            {"op": "insert_node", "name": "x", "type": "test_item"},
            "node type 'test_item'",
        ),
        ("/speech", {"op": "set_node_attrs", "node": "test", "attrs": {"text": "hi"}}, "'text'"),
        ("/pelea", {"op": "delete_node", "node": "speaking"}, "node type 'state'"),
        (
            "/pelea",
            {"op": "insert_edge", "from": "robot", "to": "speaking", "type": "is"},
            "edge type 'is'",
        ),
        (
            "/clarc_cli",
            {"op": "delete_edge", "from": "robot", "to": "speaking", "type": "is_not"},
            "entry '/clarc_*' allows none",
        ),
        (
            "/pelea",
            {"op": "set_rt", "from": "robot", "to": "speaking", "rt": {"matrix": []}},
            "edge type 'RT'",
        ),
        ("/viewer", {"op": "delete_node", "node": "test"}, "no entry of"),
    ],
)
def test_a_write_outside_the_policy_is_refused_naming_agent_op_and_rule(agent, op, named):
    core = ServerCore(graph(), policy=Policy.from_doc(POLICY))
    before = snapshot_text(core)
    result = send(core, agent, [op])
    assert isinstance(result, Rejection) and result.violation.rule == "policy"
    text = str(result.violation)
    assert agent in text and named in text and "op 0" in text, text
    assert snapshot_text(core) == before and core.seq == 0


def test_writes_inside_the_policy_go_through_and_a_node_inserted_may_be_written_on():
    core = ServerCore(graph(), policy=Policy.from_doc(POLICY))
    ops = [
        {"op": "insert_node", "name": "feeding", "type": "test_item", "attrs": {"item": "f"}},
        {"op": "insert_edge", "from": "test", "to": "feeding", "type": "is_in"},
        {"op": "set_node_attrs", "node": "test", "attrs": {"text": "Feeding"}},
        {"op": "delete_node", "node": "feeding"},
    ]
    assert not isinstance(send(core, "/pelea", ops), Rejection)
    flip = [
        {"op": "delete_edge", "from": "robot", "to": "speaking", "type": "is_not"},
        {"op": "insert_edge", "from": "robot", "to": "speaking", "type": "is"},
    ]
    assert not isinstance(send(core, "/speech", flip), Rejection)
    start = [{"op": "set_node_attrs", "node": "test", "attrs": {"item": "start"}}]
    assert not isinstance(send(core, "/clarc_cli_42", start), Rejection)  # by pattern


def test_priorities_come_from_the_policy_never_from_the_request():
    core = ServerCore(graph(), policy=Policy.from_doc(POLICY))
    claim = {"claim": [{"from": "robot", "to": "speaking"}], "priority": 99}
    held = send(core, "/speech", [], **claim)
    assert held["claims"]["granted"][0]["priority"] == 1
    flip = [{"op": "delete_edge", "from": "robot", "to": "speaking", "type": "is_not"}]
    taken = send(core, "/pelea", flip, priority=0)  # the policy's 10 > 1: it preempts
    assert not isinstance(taken, Rejection)
    assert taken["claims"]["released"][0]["reason"] == "preempted"


def test_without_a_policy_all_priorities_are_equal_so_no_one_preempts():
    core = ServerCore(graph(), policy=OPEN)
    send(core, "/speech", [], claim=[{"from": "robot", "to": "speaking"}], priority=1)
    flip = [{"op": "delete_edge", "from": "robot", "to": "speaking", "type": "is_not"}]
    result = send(core, "/anyone", flip, priority=1000)
    assert isinstance(result, Rejection) and result.violation.rule == "claimed"


@pytest.mark.parametrize(
    ("doc", "fragment"),
    [
        ({"version": 2, "agents": [{"name": "*"}]}, "version must be 1"),
        ({"version": 1, "agents": []}, "non-empty list"),
        ({"version": 1, "agents": [{"priority": 1}]}, 'needs "name"'),
        ({"version": 1, "agents": [{"name": "*", "nodes": "robot"}]}, "nodes must be a list"),
        ({"version": 1, "agents": [{"name": "*", "priority": "high"}]}, "priority"),
        ({"version": 1, "agents": [{"name": "*", "write": []}]}, "unknown keys ['write']"),
        ([], "top level"),
    ],
)
def test_a_bad_policy_file_is_named(doc, fragment):
    with pytest.raises(FormatError, match=fragment.replace("[", r"\[").replace("]", r"\]")):
        Policy.from_doc(doc, "p.yaml")


def test_the_sender_is_the_graph_s_word_and_a_different_declared_agent_is_refused():
    core = ServerCore(graph())
    ops = [{"op": "set_node_attrs", "node": "test", "attrs": {"text": "hi"}}]
    result = core.submit(json.dumps({"agent": "/speech", "ops": ops}), sender="/intruder")
    assert isinstance(result, Rejection) and result.violation.rule == "identity"
    assert "/speech" in str(result.violation) and "/intruder" in str(result.violation)
    assert core.seq == 0
    delta = core.submit(json.dumps({"ops": ops}), sender="/intruder")
    assert delta["agent"] == "/intruder"  # recorded as itself
    delta = core.submit(json.dumps({"agent": "/intruder", "ops": ops}), sender="/intruder")
    assert delta["agent"] == "/intruder"


T = "/dsr/transactions/speech"


@pytest.mark.parametrize(
    ("owner", "publishers", "agent", "intruders"),
    [
        ("speech", [("/", "speech")], "/speech", ()),
        ("speech", [("/robot", "speech")], "/robot/speech", ()),
        ("speech", [("/", "speech"), ("/", "evil")], None, ("/evil",)),
        ("speech", [("/", "evil")], None, ("/evil",)),
        ("speech", [("/", "speech"), ("/b", "speech")], None, ("/b/speech", "/speech")),
        ("speech", [("/", "speech", b"p1"), ("/", "speech", b"p1")], "/speech", ()),  # one node
        ("speech", [("/", "speech", b"p1"), ("/", "speech", b"p2")], None, ("/speech",)),
        ("speech", [], None, ()),
        (None, [("/", "old_agent")], "/old_agent", ()),
        (None, [("/", "a"), ("/", "b")], None, ()),
    ],
)
def test_a_request_topic_proves_its_sender_only_with_one_rightful_publisher(
    owner, publishers, agent, intruders
):
    verdict = sender_on(T, owner, [Publisher(*p) for p in publishers])
    assert verdict.agent == agent and verdict.intruders == intruders
    if agent is None:
        assert T in verdict.problem
        for name in intruders:
            assert name in verdict.problem


def test_a_publisher_whose_node_is_not_known_yet_gives_no_verdict_yet():
    verdict = sender_on(T, "speech", [Publisher("_NODE_NAMESPACE_UNKNOWN_", "_NODE_NAME_UNKNOWN_")])
    assert verdict.agent is None and verdict.pending and not verdict.intruders


def test_a_publisher_matched_before_the_ros_graph_lists_it_gives_no_verdict_yet():
    """A spoofer's request reached the server while the ROS graph still showed only the
    topic's owner (a loaded whole-suite run): it was taken as the owner's. DDS had matched two
    publishers; until the graph lists both, nobody is proven."""
    owner_only = [Publisher("/", "speech")]
    early = sender_on(T, "speech", owner_only, matched=2)
    assert early.agent is None and early.pending and "2 matched publishers" in early.problem
    assert sender_on(T, "speech", owner_only, matched=1).agent == "/speech"
    listed = sender_on(T, "speech", [*owner_only, Publisher("/", "test_client")], matched=2)
    assert listed.agent is None and listed.intruders == ("/test_client",) and not listed.pending


def test_a_pending_verdict_is_waited_for_longer_than_what_it_waits_for():
    """A node's name comes on a reliable topic whose lost first sample Fast DDS sends again at the
    next heartbeat (3 s by default): three of them. A killed node goes when its lease (the suite's
    Fast DDS profile) runs out."""
    unknown = sender_on(T, "speech", [Publisher("/", "_NODE_NAME_UNKNOWN_")])
    assert unknown.pending >= 3 * 3.0
    ghost = sender_on(
        T, "speech", [Publisher("/", "speech", b"old"), Publisher("/", "speech", b"new")]
    )
    profile = Path(__file__).resolve().parents[2] / "src/dsr_graph/config/fastdds_profile.xml"
    lease = re.search(r"<leaseDuration><sec>(\d+)</sec>", profile.read_text())
    assert ghost.pending > int(lease.group(1))
    proven = sender_on(T, "speech", [Publisher("/", "speech")])
    assert proven.agent == "/speech" and not proven.pending


@pytest.mark.parametrize(
    ("publishers", "liveliness", "agent"),
    [
        # a killed node beside its respawned self: its liveliness lapsed, the successor's holds
        ([("/", "speech", b"old"), ("/", "speech", b"new")], (1, 1), "/speech"),
        # both alive: two live twins, never told apart
        ([("/", "speech", b"old"), ("/", "speech", b"new")], (2, 0), None),
        # not every publisher counted (one offers no lease): not known
        ([("/", "speech", b"old"), ("/", "speech", b"new")], (1, 0), None),
        ([("/", "speech", b"old"), ("/", "speech", b"new")], None, None),
        # two namespaces: which one is alive cannot be told
        ([("/", "speech", b"old"), ("/b", "speech", b"new")], (1, 1), None),
        # one node with two endpoints beside another: the counts are per endpoint
        ([("/", "speech", b"a"), ("/", "speech", b"a"), ("/", "speech", b"b")], (1, 2), None),
        # three nodes, two of them gone quiet: the one alive is the successor
        ([("/", "speech", b"a"), ("/", "speech", b"b"), ("/", "speech", b"c")], (1, 2), "/speech"),
    ],
)
def test_a_successor_is_known_as_soon_as_only_it_is_alive(publishers, liveliness, agent):
    verdict = sender_on(T, "speech", [Publisher(*p) for p in publishers], liveliness)
    assert verdict.agent == agent
    assert bool(verdict.pending) == (agent is None)


def test_each_agent_has_its_own_request_topic():
    assert agent_topic("speech") == "dsr/transactions/speech"


def test_a_request_on_an_unproven_topic_is_refused_keeping_its_id():
    from dsr_graph.exceptions import Violation

    core = ServerCore(graph())
    result = core.unattributed('{"id": "x1", "ops": []}', Violation("identity", T, "two publish"))
    assert result.to_json()["id"] == "x1" and result.violation.rule == "identity"
    assert core.unattributed("not json", Violation("identity", T, "?")).id == ""


@pytest.mark.parametrize(
    ("agent", "target", "named"),
    [
        ("/intruder", {"node": "test"}, "no entry of policy names '/intruder'"),
        ("/speech", {"node": "test"}, "may not claim node type 'test'"),
        ("/pelea", {"from": "robot", "to": "speaking", "type": "is"}, "edge type 'is'"),
        ("/clarc_start", {"from": "test", "to": "test_part"}, "edge type '(some type)'"),
        ("/pelea", {"from": "robot", "to": "speaking"}, None),
        ("/speech", {"from": "robot", "to": "speaking"}, None),
        ("/pelea", {"node": "test_part"}, "node type 'test_part'"),
    ],
)
def test_an_agent_may_claim_only_what_it_may_write(agent, target, named):
    core = ServerCore(graph(), policy=Policy.from_doc(POLICY))
    before = snapshot_text(core)
    result = send(core, agent, [], claim=[target], lease=10)
    if named is None:
        assert not isinstance(result, Rejection), result.violation
        assert result["claims"]["granted"][0]["agent"] == agent
        return
    assert isinstance(result, Rejection)
    assert result.violation.rule == "policy" and named in str(result.violation)
    assert snapshot_text(core) == before and core.claims.all() == []
