"""Agents in the graph (model/agent_info.py): an agent writes its own info node whatever the
policy, no one else may; the server marks it gone; ``dsr agents`` lists them; a policy drafted
from a recording does not list what every agent may do anyway."""

import json

from dsr_graph.model.agent_info import GONE, READY, STARTING, info_ops, listing, states
from dsr_graph.model.graph import Graph
from dsr_graph.model.policy import Policy, observe_writes
from dsr_graph.model.transaction import apply_ops
from dsr_graph.protocol.server_core import Rejection, ServerCore

POLICY = Policy.from_doc(
    {"version": 1, "agents": [{"name": "/pelea", "nodes": ["test_item"], "attributes": ["text"]}]}
)
INFO = {"state": STARTING, "pid": 41, "host": "robot", "can_do": ["speak"], "listens_to": []}


def send(core, agent, ops):
    return core.submit(json.dumps({"ops": ops}), now=1.0, sender=agent)


def test_an_agent_describes_itself_whatever_the_policy_then_only_what_changed_is_written():
    core = ServerCore(Graph(), policy=POLICY)
    first = info_ops(core.graph, "/speech", INFO)
    assert [op["op"] for op in first] == ["insert_node"]
    assert not isinstance(send(core, "/speech", first), Rejection)  # /speech has no entry
    assert info_ops(core.graph, "/speech", INFO) == []
    again = info_ops(core.graph, "/speech", {**INFO, "state": READY})
    assert again == [{"op": "set_node_attrs", "node": "/speech", "attrs": {"state": READY}}]
    assert not isinstance(send(core, "/speech", again), Rejection)
    assert states(core.graph) == {"/speech": READY}


def test_no_one_writes_another_agents_info_node_nor_other_attributes_on_its_own():
    core = ServerCore(Graph(), policy=POLICY)
    send(core, "/speech", info_ops(core.graph, "/speech", INFO))
    forged = [{"op": "set_node_attrs", "node": "/speech", "attrs": {"state": GONE}}]
    refused = send(core, "/pelea", forged)
    assert isinstance(refused, Rejection) and refused.violation.rule == "policy"
    squatted = info_ops(core.graph, "/panel", INFO)  # a node named after someone else
    assert isinstance(send(core, "/speech", [dict(squatted[0], name="/panel")]), Rejection)
    other = [{"op": "set_node_attrs", "node": "/speech", "attrs": {"text": "hello"}}]
    assert isinstance(send(core, "/speech", other), Rejection)
    assert states(core.graph) == {"/speech": STARTING}


def test_the_server_marks_an_ended_agent_gone_once_and_the_agent_can_come_back():
    core = ServerCore(Graph(), policy=POLICY)
    send(core, "/speech", info_ops(core.graph, "/speech", {**INFO, "state": READY}))
    seq = core.seq
    delta = core.mark_gone(["/speech", "/nobody"], now=2.0)
    assert delta["agent"] == "dsr_server" and delta["seq"] == seq + 1
    assert states(core.graph) == {"/speech": GONE}
    assert core.mark_gone(["/speech"]) is None  # nothing more to mark
    back = info_ops(core.graph, "/speech", {**INFO, "state": READY})
    assert not isinstance(send(core, "/speech", back), Rejection)
    assert listing(core.graph)[0] == {"name": "/speech", **{**INFO, "state": READY}}


def test_a_drafted_policy_leaves_out_what_every_agent_may_write():
    graph, seen = Graph(), {}
    apply_ops(graph, [{"op": "insert_node", "name": "item", "type": "test_item"}])
    for ops in (
        info_ops(graph, "/speech", INFO),
        [{"op": "set_node_attrs", "node": "item", "attrs": {"text": "hi"}}],
    ):
        observe_writes(seen, graph, {"agent": "/speech", "ops": ops})
    assert seen["/speech"] == {"nodes": set(), "edges": set(), "attributes": {"text"}}


def test_an_ability_is_missing_until_a_ready_agent_in_reach_offers_it():
    from dsr_graph.model.agent_info import missing_abilities

    graph = Graph()
    assert missing_abilities(graph, ["hear"]) == []  # no agent describes itself: as before
    apply_ops(graph, info_ops(graph, "/speech", {"state": STARTING, "can_do": ["speak", "hear"]}))
    apply_ops(graph, info_ops(graph, "/panel", {"state": READY, "can_do": ["show"]}))
    assert missing_abilities(graph, ["speak", "hear", "show"]) == ["speak", "hear"]
    apply_ops(graph, info_ops(graph, "/speech", {"state": READY, "can_do": ["speak", "hear"]}))
    assert missing_abilities(graph, ["speak", "hear", "show"]) == []
    assert missing_abilities(graph, ["hear", "show"], away={"/speech"}) == ["hear"]
