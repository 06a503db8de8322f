"""Agents in the graph (model/agent_info.py): an agent writes its own info node whatever the
policy, no one else may; the server marks it gone; ``dsr agents`` lists them; a policy drafted
from a recording does not list what every agent may do anyway."""

import json

from dsr_graph.model.agent_info import GONE, READY, STARTING, info_ops, listing, run_of, states
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


def test_a_new_run_of_an_agent_reads_its_predecessor_gone_before_its_first_change():
    """The liveliness news of a killed agent, read late by a loaded server, may show no change
    at all (its lapse, its drop and its successor's match as one): the successor's first
    request, naming a run the info node does not show, tells the end all the same."""
    core = ServerCore(Graph(), policy=POLICY)

    def request(ident, ops):
        return core.submit(json.dumps({"id": ident, "ops": ops}), now=1.0, sender="/speech")

    first = {**INFO, "state": READY, "agent_run": "a1b2c3"}
    request("/speech:a1b2c3:1", info_ops(core.graph, "/speech", first))
    request("/speech:a1b2c3:2", info_ops(core.graph, "/speech", {**first, "pid": 42}))
    assert core.take_server_deltas() == []  # the same run: nothing ended
    successor = {**INFO, "state": STARTING, "pid": 43, "agent_run": "d4e5f6"}
    delta = request("/speech:d4e5f6:1", info_ops(core.graph, "/speech", successor))
    (gone,) = core.take_server_deltas()
    assert gone["seq"] == delta["seq"] - 1 and gone["agent"] == "dsr_server"
    assert gone["ops"] == [{"op": "set_node_attrs", "node": "/speech", "attrs": {"state": GONE}}]
    assert states(core.graph) == {"/speech": STARTING}
    request("/speech:d4e5f6:2", [])  # the info node shows its run now: told once
    assert core.take_server_deltas() == []
    # ids that are not the runtime's (a tool's, another agent's) tell nothing
    core.submit(json.dumps({"id": "x", "ops": []}), now=1.0, sender="/speech")
    core.submit(json.dumps({"id": "/other:zz:1", "ops": []}), now=1.0, sender="/speech")
    assert core.take_server_deltas() == []


def test_a_request_id_names_its_run_only_in_the_runtimes_form():
    assert run_of("/speech:a1b2c3:7", "/speech") == "a1b2c3"
    assert run_of("/ns/speech:a1b2c3:7", "/ns/speech") == "a1b2c3"
    for ident, agent in (
        ("/speech:a1b2c3:7", "/panel"),
        ("/speech::7", "/speech"),
        ("/speech:a1b2c3:x", "/speech"),
        ("free-form", "/speech"),
        (None, "/s"),
    ):
        assert run_of(ident, agent) is None


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
