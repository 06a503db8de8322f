"""The options of an item as the DSR carries them (pure): PELEA writes them on the item's node
(``item_<key>``: ``options``, ``option_points``, ``option_words``) when a test starts, so the
agents that hear or show answers need no copy of any test's table."""

from __future__ import annotations

from clarc_agents.definitions import Item, Option
from dsr_graph.model.graph import Graph


def item_node(key: str) -> str:
    return f"item_{key}"


def item_in(graph: Graph, key: str) -> Item | None:
    """Item ``key`` with its options from its node; None when the DSR does not carry them."""
    node = graph.find(item_node(key))
    if node is None:
        return None
    texts = node.attrs.get("options")
    points = node.attrs.get("option_points")
    words = node.attrs.get("option_words")
    if not (isinstance(texts, list) and isinstance(points, list) and isinstance(words, list)):
        return None
    if not len(texts) == len(points) == len(words):
        return None
    options = tuple(
        Option(int(p), str(t), "", tuple(w for w in str(ws).split("|") if w))
        for t, p, ws in zip(texts, points, words, strict=True)
    )
    return Item(key, str(node.attrs.get("title", key)), "", options)
