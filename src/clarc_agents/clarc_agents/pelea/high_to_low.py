"""HighToLow: a high-level action of the plan as changes to the DSR (pure). PELEA never commands
an agent: it writes the state that makes the agent act (paper, Fig. 1 right)."""

from __future__ import annotations

from typing import Any

from clarc_agents.behaviours.item_options import answer_attrs, item_node
from clarc_agents.definitions import Definition
from clarc_agents.questionnaire import confirmation
from clarc_agents.questionnaire.record import ItemResult
from clarc_agents.sentence import Sentence
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
        "shows": list(sentence.shows),
        "input": sentence.input,
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


REQUEST = ("requested_patient", "requested", "requested_test", "requested_patient_id")


def request_start(
    patient: str,
    requested: str,
    test: str = "barthel",
    patient_id: int | None = None,
    graph: Graph | None = None,
) -> dict[str, Any]:
    """The clinician pressed Start for a test (``barthel``, ``mmse``, ``get_up_and_go``, ...)
    and a patient (their record's id, if the Start named one): the request waits on the test
    node until PELEA takes it. ``graph``: the DSR as the sender sees it, so that an id left by
    an earlier request not taken yet goes."""
    attrs: dict[str, Any] = {
        "requested_patient": patient,
        "requested": requested,
        "requested_test": test,
    }
    ops: list[dict[str, Any]] = []
    if patient_id is not None:
        attrs["requested_patient_id"] = patient_id
    elif graph is not None and "requested_patient_id" in graph.node("test").attrs:
        ops.append({"op": "remove_node_attrs", "node": "test", "names": ["requested_patient_id"]})
    return {"ops": ops + [{"op": "set_node_attrs", "node": "test", "attrs": attrs}]}


def patient_attrs(graph: Graph) -> tuple[list[dict[str, Any]], dict[str, Any]]:
    """The patient's record id from the Start request onto the running test (ops removing an
    earlier test's id first, attrs to set): results name the record, not only the name."""
    test = graph.node("test").attrs
    if "requested_patient_id" in test:
        return [], {"patient_id": int(test["requested_patient_id"])}
    if "patient_id" in test:
        return [{"op": "remove_node_attrs", "node": "test", "names": ["patient_id"]}], {}
    return [], {}


def take_request(graph: Graph, patient: str) -> tuple[list[dict], list[dict]]:
    """(preconditions, ops) taking the Start request for ``patient`` (CAS on it), if any."""
    test = graph.node("test")
    if "requested_patient" not in test.attrs:
        return [], []
    check = {"check": "attr_equals", "node": "test", "attr": "requested_patient", "value": patient}
    names = [n for n in REQUEST if n in test.attrs]
    return [check], [{"op": "remove_node_attrs", "node": "test", "names": names}]


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
    attrs = {"item": confirmation.KEY, **answer_attrs(confirmation.ITEM)}
    ops.append({"op": "insert_node", "name": name, "type": "test_item", "attrs": attrs})
    return {"preconditions": checks, "ops": ops}


def refuse_start(graph: Graph, patient: str) -> dict[str, Any]:
    """A Start while a test runs: the request is dropped (CAS on the same request)."""
    checks, ops = take_request(graph, patient)
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
    return {"ops": [{"op": "set_node_attrs", "node": item_node(result.item), "attrs": attrs}]}


def record_test(**attrs: Any) -> dict[str, Any]:
    """Progress of the test on its node (greeted, explained, said_goodbye, person_lost_count,
    finished): what a restarted PELEA reads to go on from where the test was."""
    return {"ops": [{"op": "set_node_attrs", "node": "test", "attrs": attrs}]}


def current_item(item: str) -> dict[str, Any]:
    return {"ops": [{"op": "set_node_attrs", "node": "test", "attrs": {"item": item}}]}


def call_clinician(graph: Graph) -> dict[str, Any]:
    ops: list[dict[str, Any]] = [
        {"op": "set_node_attrs", "node": "test", "attrs": {"clinician_called": True}}
    ]
    if graph.edge("test", "clinician", "requests") is None:
        ops.append({"op": "insert_edge", "from": "test", "to": "clinician", "type": "requests"})
    return {"ops": ops}


def finish_test(graph: Graph) -> dict[str, Any]:
    """The result is stored: the test is over."""
    ops: list[dict[str, Any]] = [
        {"op": "set_node_attrs", "node": "test", "attrs": {"status": "finished"}}
    ]
    if graph.edge("test", "clinician", "requests") is not None:
        ops.append({"op": "delete_edge", "from": "test", "to": "clinician", "type": "requests"})
    return {"ops": ops}


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
