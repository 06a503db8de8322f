"""LowToHigh of a questionnaire (pure): the answer window and the item nodes read back as the
facts Monitoring reasons about, and the record a restarted PELEA goes on from."""

from __future__ import annotations

from dataclasses import dataclass

from clarc_agents.definitions import Definition
from clarc_agents.questionnaire.item_options import hearings, item_node
from clarc_agents.questionnaire.record import QuestionnaireRecord
from clarc_agents.test_node import person_present
from dsr_graph.model.graph import Graph
from dsr_graph.rules.matching import match
from dsr_graph.rules.syntax import Pattern

ANSWER = [Pattern("edge", "person", "answer", "got", {"item": "$item"})]


@dataclass(frozen=True)
class Answer:
    """answer(item, outcome, points, via, heard): outcome is answered, skip, not_understood or
    unsure (an option heard, not for sure: ``points`` is the option, to confirm).
    A drawing is answered without points (the clinician scores it)."""

    item: str
    outcome: str
    points: int | None = None
    via: str | None = None
    heard: str = ""
    drawing: str = ""
    audio: str = ""  # the clip of what was said (voice), if the recogniser kept one
    confidence: float | None = None  # how sure the recogniser was of what was heard (voice)


def answer(graph: Graph) -> Answer | None:
    found = next(match(graph, ANSWER), None)
    if found is None:
        return None
    attrs = graph.edge("person", "answer", "got").attrs
    heard, audio = str(attrs.get("heard", "")), str(attrs.get("audio", ""))
    sure = attrs.get("confidence")
    confidence = float(sure) if isinstance(sure, (int, float)) else None
    said = {"heard": heard, "audio": audio, "confidence": confidence}
    if attrs.get("skip"):
        return Answer(found["$item"], "skip", **said)
    if attrs.get("unsure") and isinstance(attrs.get("answer"), (int, float)):
        points = int(attrs["answer"])
        return Answer(found["$item"], "unsure", points, "voice", **said)
    if not attrs.get("understood", False):
        return Answer(found["$item"], "not_understood", **said)
    points = int(attrs["answer"]) if "answer" in attrs else None
    drawing = str(attrs.get("drawing", ""))
    return Answer(found["$item"], "answered", points, attrs.get("via"), drawing=drawing, **said)


def window_interrupted(graph: Graph) -> bool:
    """The agent listening to the patient was restarted during the open answer window."""
    edge = graph.edge("person", "answer", "waiting")
    return edge is not None and bool(edge.attrs.get("interrupted"))


def touched_so_far(graph: Graph) -> tuple[int, str] | None:
    """The points and shapes of a three-stage command under way in the open window (Panel keeps
    them there), or None."""
    edge = graph.edge("person", "answer", "waiting")
    if edge is None or "touched_points" not in edge.attrs:
        return None
    return int(edge.attrs["touched_points"]), str(edge.attrs.get("touched", ""))


def hearing_since(graph: Graph) -> float | None:
    """When the patient began to speak in the open answer window (epoch s), if they did: their
    words may still be on their way through the recogniser."""
    edge = graph.edge("person", "answer", "waiting")
    stamp = edge.attrs.get("hearing") if edge is not None else None
    return float(stamp) if isinstance(stamp, (int, float)) else None


def window_untaken(graph: Graph) -> bool:
    """The answer window is open but no agent started listening (``can`` still there): no one
    could have heard the patient."""
    return graph.edge("person", "answer", "can") is not None


def record(graph: Graph, definition: Definition) -> QuestionnaireRecord:
    """The running (or last) test as its record, read from the test node and the item nodes."""
    test = graph.node("test").attrs
    rec = QuestionnaireRecord(
        definition, str(test.get("patient", "")), str(test.get("started", ""))
    )
    rec.finished = test.get("finished")
    rec.patient_id = int(test["patient_id"]) if "patient_id" in test else None
    rec.clinician_called = bool(test.get("clinician_called", False))
    rec.person_lost_count = int(test.get("person_lost_count", 0))
    for key in definition.order:
        node = graph.find(item_node(key))
        if node is None:
            continue
        result = rec.items[key]
        result.attempts = int(node.attrs.get("attempts", 0))
        result.outcomes = list(node.attrs.get("outcomes", []))
        result.heard = str(node.attrs.get("heard", ""))
        result.audio = [str(a) for a in node.attrs.get("audio_clips", [])]
        result.hearings = hearings(graph, key)
        status = node.attrs.get("status")
        if status == "answered":
            result.answered, result.via = True, node.attrs.get("via")
            result.points = int(node.attrs["answer"]) if "answer" in node.attrs else None
            result.drawing = str(node.attrs.get("drawing", ""))
        result.closed = status in ("answered", "unanswered")
    return rec


def facts(graph: Graph, definition: Definition) -> frozenset[str]:
    """The high-level state of a running test, read from the DSR: what a restarted PELEA plans
    from. An item not closed yet (the one in progress) is pending: it is asked again."""
    test = graph.node("test").attrs
    rec = record(graph, definition)
    state = {"(started)", f"(current {test.get('item', definition.order[0])})"}
    state.add("(person-present)" if person_present(graph) else "(person-absent)")
    for flag in ("greeted", "explained", "said-goodbye"):
        if test.get(flag.replace("-", "_")):
            state.add(f"({flag})")
    for key in definition.order:
        state.add(f"(closed {key})" if rec.items[key].closed else f"(pending {key})")
    needed = not rec.clinician_called and len(rec.unanswered) >= 2
    state.add("(clinician-needed)" if needed else "(clinician-ok)")
    return frozenset(state)
