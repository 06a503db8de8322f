"""HighToLow of a questionnaire (pure): its actions as changes to the DSR. The test node with one
node per item (how it is answered), the answer window Speech and Panel listen in, each item's
result as far as it went. What every test shares is ``test_node.py``, the sentences
``pelea/high_to_low.py``."""

from __future__ import annotations

from typing import Any

from clarc_agents.definitions import Definition
from clarc_agents.questionnaire import confirmation
from clarc_agents.questionnaire.item_options import answer_attrs, item_node
from clarc_agents.questionnaire.record import ItemResult
from clarc_agents.test_node import patient_attrs, take_request
from dsr_graph.model.graph import Graph


def open_answer(graph: Graph, item: str) -> dict[str, Any]:
    """person can answer: Speech starts listening, Panel takes taps (Algorithm 3). A window an
    earlier close did not remove (it lost a race with a restart) is replaced in the same step."""
    stale = [k for k in ("can", "waiting") if graph.edge("person", "answer", k) is not None]
    edge = {"from": "person", "to": "answer"}
    return {
        "preconditions": [
            {"check": "edge_exists", "from": "person", "to": "robot", "type": "is_with"},
            {"check": "edge_absent", "from": "person", "to": "answer", "type": "got"},
            *({"check": "edge_exists", **edge, "type": k} for k in stale),
        ],
        "ops": [
            *({"op": "delete_edge", **edge, "type": k} for k in stale),
            {
                "op": "insert_edge",
                "from": "person",
                "to": "answer",
                "type": "can",
                "attrs": {"item": item},
            },
        ],
    }


def close_answer(graph: Graph, as_read: bool = False) -> dict[str, Any] | None:
    """Stop waiting (time is up, or the person left): remove can/waiting, as a compare-and-set so
    that an answer arriving at the same moment wins; ``as_read``: also refused if the window
    changed since ``graph`` (a shape touched meanwhile: what it holds is read again)."""
    for kind in ("waiting", "can"):
        edge = graph.edge("person", "answer", kind)
        if edge is not None:
            at = {"from": "person", "to": "answer", "type": kind}
            checks = [{"check": "edge_exists", **at}]
            if as_read:
                checks.append({"check": "version_equals", **at, "version": edge.version})
            return {"preconditions": checks, "ops": [{"op": "delete_edge", **at}]}
    return None


def consume_answer() -> dict[str, Any]:
    return {
        "preconditions": [
            {"check": "edge_exists", "from": "person", "to": "answer", "type": "got"}
        ],
        "ops": [{"op": "delete_edge", "from": "person", "to": "answer", "type": "got"}],
    }


def start_test(graph: Graph, patient: str, started: str, definition: Definition) -> dict[str, Any]:
    """The test is running: on the test node the patient, the test, the time and everything
    PELEA needs to resume after a restart (flags of the steps done, the clinician called, how
    often the person left); one node per item for its answer, carrying how it is answered (its
    options, or its parts with the words that recognise them: filled for today and here). A
    Start request for this patient is taken (CAS)."""
    test = graph.node("test")
    forget, patient_id = patient_attrs(graph)
    checks, ops = take_request(graph, patient)
    ops = forget + ops
    stale = [k for k in ("finished",) if k in test.attrs]
    if stale:
        ops.append({"op": "remove_node_attrs", "node": "test", "names": stale})
    ops.append(
        {
            "op": "set_node_attrs",
            "node": "test",
            "attrs": {
                **patient_id,
                "patient": patient,
                "kind": definition.test,
                "language": definition.language,
                "status": "running",
                "started": started,
                "item": definition.order[0],
                "greeted": False,
                "explained": False,
                "said_goodbye": False,
                "clinician_called": False,
                "person_lost_count": 0,
            },
        }
    )
    for position, item in enumerate(definition.items, 1):
        name = item_node(item.key)
        if name in graph:
            ops.append({"op": "delete_node", "node": name})  # a previous test's record
        ops.append(
            {
                "op": "insert_node",
                "name": name,
                "type": "test_item",
                "attrs": {
                    "item": item.key,
                    "position": position,
                    "attempts": 0,
                    "status": "asking",
                    **answer_attrs(item),
                },
            }
        )
        ops.append({"op": "insert_edge", "from": "test", "to": name, "type": "has"})
    # the yes or no that confirms an answer heard not for sure, answered as any choose item
    name = item_node(confirmation.KEY)
    if name in graph:
        ops.append({"op": "delete_node", "node": name})
    attrs = {"item": confirmation.KEY, **answer_attrs(confirmation.item_in(definition.language))}
    ops.append({"op": "insert_node", "name": name, "type": "test_item", "attrs": attrs})
    return {"preconditions": checks, "ops": ops}


def record_item(result: ItemResult) -> dict[str, Any]:
    """An item as far as it went: its windows and how each ended, and its answer or that it was
    left unanswered (what observers and a restarted PELEA read)."""
    attrs: dict[str, Any] = {
        "attempts": result.attempts,
        "status": result.status,
        "outcomes": list(result.outcomes),
        "heard": result.heard,
    }
    if result.points is not None:
        attrs.update(answer=result.points)
    if result.answered:
        attrs.update(via=result.via)
    if result.drawing:
        attrs.update(drawing=result.drawing)
    if result.audio:
        attrs.update(audio_clips=list(result.audio))
    if result.hearings:
        attrs.update(
            hearings=[text for text, _ in result.hearings],
            hearing_confidences=[confidence for _, confidence in result.hearings],
        )
    return {"ops": [{"op": "set_node_attrs", "node": item_node(result.item), "attrs": attrs}]}


def current_item(item: str) -> dict[str, Any]:
    return {"ops": [{"op": "set_node_attrs", "node": "test", "attrs": {"item": item}}]}


def reset_answer(graph: Graph) -> dict[str, Any] | None:
    """Close whatever answer window a previous run of PELEA left (can, waiting or got)."""
    kinds = [k for k in ("can", "waiting", "got") if graph.edge("person", "answer", k) is not None]
    if not kinds:
        return None
    edge = {"from": "person", "to": "answer"}
    return {
        "preconditions": [{"check": "edge_exists", **edge, "type": k} for k in kinds],
        "ops": [{"op": "delete_edge", **edge, "type": k} for k in kinds],
    }
