"""HighToLow: a high-level action of the plan as changes to the DSR (pure). PELEA never commands
an agent: it writes the state that makes the agent act (paper, Fig. 1 right)."""

from __future__ import annotations

from typing import Any

from clarc_agents.barthel.items import ORDER
from clarc_agents.barthel.sentences import Sentence
from dsr_graph.model.graph import Graph


def _reset_channel(graph: Graph, channel: str) -> list[dict[str, Any]]:
    """robot finish <channel> -> robot is_not <channel>, so the agent can take the next one."""
    if graph.edge("robot", channel, "finish") is not None:
        return [
            {"op": "delete_edge", "from": "robot", "to": channel, "type": "finish"},
            {"op": "insert_edge", "from": "robot", "to": channel, "type": "is_not"},
        ]
    if graph.edge("robot", channel, "is_not") is None:
        return [{"op": "insert_edge", "from": "robot", "to": channel, "type": "is_not"}]
    return []


def say(graph: Graph, sentence: Sentence, sid: int) -> dict[str, Any]:
    """The sentence on test -is_in-> test_part (paper, Fig. 3), for Speech and Panel."""
    attrs = {
        "text": sentence.text,
        "sentence_id": sid,
        "needs_person": sentence.needs_person,
        "item": sentence.item,
        "options": list(sentence.options),
        "option_points": list(sentence.option_points),
    }
    ops = _reset_channel(graph, "speaking") + _reset_channel(graph, "showing")
    if graph.edge("test", "test_part", "is_in") is None:
        ops.append(
            {
                "op": "insert_edge",
                "from": "test",
                "to": "test_part",
                "type": "is_in",
                "attrs": attrs,
            }
        )
    else:
        ops.append(
            {
                "op": "set_edge_attrs",
                "from": "test",
                "to": "test_part",
                "type": "is_in",
                "attrs": attrs,
            }
        )
    return {
        "preconditions": [
            {"check": "edge_absent", "from": "robot", "to": "speaking", "type": "is"},
            {"check": "edge_absent", "from": "robot", "to": "showing", "type": "is"},
        ],
        "ops": ops,
    }


def open_answer(item: str) -> dict[str, Any]:
    """person can answer: Speech starts listening, Panel takes taps (Algorithm 3)."""
    return {
        "preconditions": [
            {"check": "edge_exists", "from": "person", "to": "robot", "type": "is_with"},
            {"check": "edge_absent", "from": "person", "to": "answer", "type": "got"},
        ],
        "ops": [
            {
                "op": "insert_edge",
                "from": "person",
                "to": "answer",
                "type": "can",
                "attrs": {"item": item},
            }
        ],
    }


def close_answer(graph: Graph) -> dict[str, Any] | None:
    """Stop waiting (time is up, or the person left): remove can/waiting, as a compare-and-set so
    that an answer arriving at the same moment wins."""
    for kind in ("waiting", "can"):
        if graph.edge("person", "answer", kind) is not None:
            return {
                "preconditions": [
                    {"check": "edge_exists", "from": "person", "to": "answer", "type": kind}
                ],
                "ops": [{"op": "delete_edge", "from": "person", "to": "answer", "type": kind}],
            }
    return None


def consume_answer() -> dict[str, Any]:
    return {
        "preconditions": [
            {"check": "edge_exists", "from": "person", "to": "answer", "type": "got"}
        ],
        "ops": [{"op": "delete_edge", "from": "person", "to": "answer", "type": "got"}],
    }


def item_node(item: str) -> str:
    return f"item_{item}"


def start_test(graph: Graph, patient: str, started: str) -> dict[str, Any]:
    """The test is running: patient and time on the test node, one node per item for its answer."""
    ops: list[dict[str, Any]] = [
        {
            "op": "set_node_attrs",
            "node": "test",
            "attrs": {
                "patient": patient,
                "status": "running",
                "started": started,
                "item": ORDER[0],
            },
        }
    ]
    for position, item in enumerate(ORDER, 1):
        name = item_node(item)
        if name in graph:
            ops.append({"op": "delete_node", "node": name})  # a previous test's record
        ops.append(
            {
                "op": "insert_node",
                "name": name,
                "type": "test_item",
                "attrs": {"item": item, "position": position, "attempts": 0},
            }
        )
        ops.append({"op": "insert_edge", "from": "test", "to": name, "type": "has"})
    return {"ops": ops}


def record_item(
    item: str, attempts: int, points: int | None = None, via: str | None = None
) -> dict[str, Any]:
    attrs: dict[str, Any] = {"attempts": attempts}
    if points is not None:
        attrs.update(answer=points, via=via)
    return {"ops": [{"op": "set_node_attrs", "node": item_node(item), "attrs": attrs}]}


def current_item(item: str) -> dict[str, Any]:
    return {"ops": [{"op": "set_node_attrs", "node": "test", "attrs": {"item": item}}]}


def call_clinician(graph: Graph) -> dict[str, Any] | None:
    if graph.edge("test", "clinician", "requests") is not None:
        return None
    return {"ops": [{"op": "insert_edge", "from": "test", "to": "clinician", "type": "requests"}]}


def finish_test(graph: Graph, finished: str) -> dict[str, Any]:
    ops: list[dict[str, Any]] = [
        {
            "op": "set_node_attrs",
            "node": "test",
            "attrs": {"status": "finished", "finished": finished},
        }
    ]
    if graph.edge("test", "clinician", "requests") is not None:
        ops.append({"op": "delete_edge", "from": "test", "to": "clinician", "type": "requests"})
    return {"ops": ops}
