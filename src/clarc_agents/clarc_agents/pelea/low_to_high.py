"""LowToHigh: the DSR's binary predicates as the n-ary facts Monitoring reasons about (pure).

Each fact is read with the grammar's pattern matcher, so the symbols PELEA relies on are
declared here, in one place, as data."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from dsr_graph.model.graph import Graph
from dsr_graph.rules.matching import match
from dsr_graph.rules.syntax import Pattern

PATTERNS = {
    "person_present": [Pattern("edge", "person", "robot", "is_with")],
    "answer": [Pattern("edge", "person", "answer", "got", {"item": "$item"})],
    "speech_finished": [Pattern("edge", "robot", "speaking", "finish", {"sentence_id": "$sid"})],
    "panel_finished": [Pattern("edge", "robot", "showing", "finish", {"sentence_id": "$sid"})],
    "busy_speaking": [Pattern("edge", "robot", "speaking", "is")],
    "busy_showing": [Pattern("edge", "robot", "showing", "is")],
}


@dataclass(frozen=True)
class Answer:
    """answer(item, outcome, points, via, heard): outcome is answered, skip or not_understood."""

    item: str
    outcome: str
    points: int | None = None
    via: str | None = None
    heard: str = ""


def _first(graph: Graph, name: str) -> dict[str, Any] | None:
    return next(match(graph, PATTERNS[name]), None)


def person_present(graph: Graph) -> bool:
    return _first(graph, "person_present") is not None


def answer(graph: Graph) -> Answer | None:
    found = _first(graph, "answer")
    if found is None:
        return None
    attrs = graph.edge("person", "answer", "got").attrs
    if attrs.get("skip"):
        return Answer(found["$item"], "skip", heard=attrs.get("heard", ""))
    if not attrs.get("understood", False):
        return Answer(found["$item"], "not_understood", heard=attrs.get("heard", ""))
    return Answer(
        found["$item"], "answered", int(attrs["answer"]), attrs.get("via"), attrs.get("heard", "")
    )


def sentence_done(graph: Graph, sid: int) -> bool:
    """Both the voice and the screen finished sentence ``sid``."""
    spoken = _first(graph, "speech_finished")
    shown = _first(graph, "panel_finished")
    return bool(spoken and shown and spoken["$sid"] == sid and shown["$sid"] == sid)


def channels_idle(graph: Graph) -> bool:
    """Neither Speech nor Panel is in the middle of an action (a new sentence may be written)."""
    return _first(graph, "busy_speaking") is None and _first(graph, "busy_showing") is None


def last_sentence_id(graph: Graph) -> int:
    edge = graph.edge("test", "test_part", "is_in")
    return int(edge.attrs.get("sentence_id", 0)) if edge is not None else 0
