"""HighToLow of the core (pure): a sentence for Speech and Panel as changes to the DSR. PELEA
never commands an agent: it writes the state that makes the agent act (paper, Fig. 1 right).
Each test writes its own layout (``questionnaire/high_to_low.py``, ``gug/high_to_low.py``), and
the test node every test shares is ``test_node.py``."""

from __future__ import annotations

from typing import Any

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
