"""LowToHigh of the core (pure): the sentences as the DSR shows them, Speech and Panel taking and
finishing them, read with the grammar's pattern matcher, so the symbols PELEA relies on are
declared here as data. Each test reads its own layout (``questionnaire/low_to_high.py``, the
Get Up & Go's gait node), and the test node every test shares is ``test_node.py``."""

from __future__ import annotations

from typing import Any

from dsr_graph.model.graph import Graph
from dsr_graph.rules.matching import match
from dsr_graph.rules.syntax import Pattern

PATTERNS = {
    "speech_finished": [Pattern("edge", "robot", "speaking", "finish", {"sentence_id": "$sid"})],
    "panel_finished": [Pattern("edge", "robot", "showing", "finish", {"sentence_id": "$sid"})],
    "busy_speaking": [Pattern("edge", "robot", "speaking", "is")],
    "busy_showing": [Pattern("edge", "robot", "showing", "is")],
}


def _first(graph: Graph, name: str) -> dict[str, Any] | None:
    return next(match(graph, PATTERNS[name]), None)


def sentence_done(graph: Graph, sid: int) -> bool:
    """Both the voice and the screen finished sentence ``sid``."""
    spoken = _first(graph, "speech_finished")
    shown = _first(graph, "panel_finished")
    return bool(spoken and shown and spoken["$sid"] == sid and shown["$sid"] == sid)


def speech_ended_at(graph: Graph, sid: int) -> float | None:
    """When the speaker finished sentence ``sid`` (epoch seconds), if Speech said so."""
    edge = graph.edge("robot", "speaking", "finish")
    if edge is None or edge.attrs.get("sentence_id") != sid or "ended_at" not in edge.attrs:
        return None
    return float(edge.attrs["ended_at"])


def sentence_taken(graph: Graph, sid: int) -> bool:
    """Speech or Panel started sentence ``sid`` (or already finished it): an agent that can
    reach the DSR took it."""
    finished = [_first(graph, "speech_finished"), _first(graph, "panel_finished")]
    return not channels_idle(graph) or any(f and f["$sid"] == sid for f in finished)


def channels_idle(graph: Graph) -> bool:
    """Neither Speech nor Panel is in the middle of an action (a new sentence may be written)."""
    return not busy_channels(graph)


def busy_channels(graph: Graph) -> list[str]:
    """What the robot is in the middle of: "speaking" (Speech), "showing" (Panel)."""
    busy = (("speaking", "busy_speaking"), ("showing", "busy_showing"))
    return [what for what, pattern in busy if _first(graph, pattern) is not None]


def last_sentence_id(graph: Graph) -> int:
    edge = graph.edge("test", "test_part", "is_in")
    return int(edge.attrs.get("sentence_id", 0)) if edge is not None else 0
