"""How an item is answered, as the DSR carries it (pure): PELEA writes it on the item's node
(``item_<key>``) when a test starts, so the agents that hear, show or see answers need no copy
of any test's table. ``answer_kind`` is the item's kind (choose, words, touches, drawing, eyes);
``question`` and ``ask`` what the robot asks (a recogniser's context);
a ``choose`` item has ``options``, ``option_points`` and ``option_words``; a ``words`` or
``touches`` item ``parts`` (the words that recognise each part) and ``parts_spelt`` (each part's
first phrase as written, a name with its capitals); the points it is worth are
``max_points``; ``language`` what it is asked and answered in (an item without it: English).
Several phrases of one option or part are joined by "|"."""

from __future__ import annotations

from typing import Any

from clarc_agents import languages
from clarc_agents.definitions import KINDS, Item, Option, Part
from dsr_graph.model.graph import Graph


def item_node(key: str) -> str:
    return f"item_{key}"


def answer_attrs(item: Item) -> dict[str, Any]:
    """What the item's node carries for the agents that take its answers."""
    attrs: dict[str, Any] = {"answer_kind": item.kind, "max_points": item.max}
    attrs["language"] = item.language
    # what the robot asks, for a recogniser's context (asr/expectations.py)
    attrs["question"] = item.question
    if item.ask:
        attrs["ask"] = item.ask
    if item.kind == "choose":
        attrs.update(
            options=[o.text for o in item.options],
            option_points=[float(o.points) for o in item.options],
            option_words=["|".join(o.keywords) for o in item.options],
        )
    if item.parts:
        attrs["parts"] = ["|".join(p.keywords) for p in item.parts]
        attrs["parts_spelt"] = [p.spelt or p.keywords[0] for p in item.parts]
    return attrs


def hearings(graph: Graph, key: str) -> list[tuple[str, float]]:
    """What was heard to item ``key`` in its earlier windows without being understood for sure,
    and how sure (its node's ``hearings`` and ``hearing_confidences``, PELEA's record)."""
    node = graph.find(item_node(key))
    if node is None:
        return []
    texts, confidences = node.attrs.get("hearings", []), node.attrs.get("hearing_confidences", [])
    if not isinstance(texts, list) or not isinstance(confidences, list):
        return []
    return [(str(t), float(c)) for t, c in zip(texts, confidences, strict=False)]


def item_in(graph: Graph, key: str) -> Item | None:
    """Item ``key`` as its node says it is answered; None when the DSR does not say."""
    node = graph.find(item_node(key))
    if node is None:
        return None
    kind = node.attrs.get("answer_kind", "choose")  # written before items had kinds: choose
    if kind not in KINDS:
        return None
    title = str(node.attrs.get("title", key))
    language = str(node.attrs.get("language", languages.DEFAULT))
    if language not in languages.codes():
        return None  # understood by no rules here
    question, ask = str(node.attrs.get("question", "")), str(node.attrs.get("ask", ""))
    if kind != "choose":
        parts = node.attrs.get("parts", [])
        if not isinstance(parts, list):
            return None
        numbers = [str(p).split("|")[0].lstrip("-") for p in parts]
        if kind == "serial" and not (len(parts) >= 2 and all(n.isdigit() for n in numbers)):
            return None  # not a serial subtraction's numbers: nothing to score against
        spelt = node.attrs.get("parts_spelt", [])
        if not (isinstance(spelt, list) and len(spelt) == len(parts)):
            spelt = [""] * len(parts)  # written before parts were spelt: the keywords'
        return Item(
            key,
            title,
            question,
            kind=kind,
            ask=ask,
            parts=tuple(
                Part(str(i), _phrases(ws), str(s))
                for i, (ws, s) in enumerate(zip(parts, spelt, strict=True))
            ),
            most=int(node.attrs.get("max_points", 0)),
            language=language,
        )
    texts = node.attrs.get("options")
    points = node.attrs.get("option_points")
    words = node.attrs.get("option_words")
    if not (isinstance(texts, list) and isinstance(points, list) and isinstance(words, list)):
        return None
    if not len(texts) == len(points) == len(words):
        return None
    options = tuple(
        Option(int(p), str(t), "", _phrases(ws))
        for t, p, ws in zip(texts, points, words, strict=True)
    )
    return Item(key, title, question, options, ask=ask, language=language)


def awaited_item(graph: Graph) -> Item | None:
    """The item whose answer is awaited now (a listener took the window), as its node says it
    is answered; None when no answer is awaited."""
    waiting = graph.edge("person", "answer", "waiting")
    return None if waiting is None else item_in(graph, str(waiting.attrs.get("item", "")))


def item_on_screen(graph: Graph) -> str:
    """The key of the item whose sentence is on test -is_in-> test_part ("" when none)."""
    shown = graph.edge("test", "test_part", "is_in")
    return "" if shown is None else str(shown.attrs.get("item", ""))


def _phrases(joined: Any) -> tuple[str, ...]:
    return tuple(w for w in str(joined).split("|") if w)
