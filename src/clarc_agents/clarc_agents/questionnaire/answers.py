"""Understanding an answer to an item (pure).

Said, to a ``choose`` item: an utterance chooses an option by number ("option two", "number 2",
"the second one"), or by the option's keywords (phrases; the option with the most hits wins, a
tie is not understood). Said, to a ``words`` item: a point for each part recognised; any words
but hesitations are an answer ("I don't know" is one, worth 0). Said, to a ``serial`` item (the
serial sevens): a point for each number that is the one said before it, or the start, minus the
step (93, 85, 78: 2 points). Touched, on a ``touches`` item:
a point for each part touched in its place in the order. "skip" / "next question" asks to skip
the item. Anything else is not understood.
"""

from __future__ import annotations

import re
from dataclasses import dataclass

from clarc_agents.definitions import Item, serial_numbers

SKIP = ("skip", "next question", "pass", "go to the next")
NUMBERS = {
    "one": 1,
    "first": 1,
    "1": 1,
    "two": 2,
    "second": 2,
    "2": 2,
    "three": 3,
    "third": 3,
    "3": 3,
    "four": 4,
    "fourth": 4,
    "4": 4,
}
# sounds that are no answer at all (what a recogniser makes of mumbling)
HESITATIONS = frozenset("mmh mm hmm hm eh er uh um ah oh brr the a an and".split())
_BY_NUMBER = re.compile(r"\b(?:option|number)\s+(\w+)\b|\bthe\s+(first|second|third|fourth)\b")


@dataclass(frozen=True)
class Understanding:
    kind: str  # "answer", "skip" or "not_understood"
    points: int | None = None


def normalise(text: str) -> str:
    return " " + re.sub(r"[^a-z0-9' ]+", " ", text.lower()).strip() + " "


def understand(item: Item, text: str) -> Understanding:
    said = normalise(text)
    if not said.strip():
        return Understanding("not_understood")
    if any(f" {s} " in said for s in SKIP):
        return Understanding("skip")
    if item.kind in ("words", "serial"):
        if set(said.split()) <= HESITATIONS:
            return Understanding("not_understood")
        if item.kind == "serial":
            return Understanding("answer", serial_points(item, numbers_in(said)))
        return Understanding("answer", sum(_heard(part.keywords, said) for part in item.parts))
    m = _BY_NUMBER.search(said)
    if m:
        n = NUMBERS.get(m.group(1) or m.group(2))
        if n is not None and 1 <= n <= len(item.options):
            return Understanding("answer", item.options[n - 1].points)
    hits = [(sum(f" {k} " in said for k in o.keywords), o.points) for o in item.options]
    best = max(h for h, _ in hits)
    winners = [p for h, p in hits if h == best]
    if best == 0 or len(winners) > 1:
        return Understanding("not_understood")
    return Understanding("answer", winners[0])


def _heard(keywords: tuple[str, ...], said: str) -> bool:
    return any(f" {normalise(k).strip()} " in said for k in keywords)


def touched_in_order(item: Item, targets: list[str]) -> int:
    """The points of the targets touched on a ``touches`` item: one per part touched in its
    place (the first touch the first part, ...)."""
    touched = [t.strip().lower() for t in targets]
    return sum(
        1 for part, target in zip(item.parts, touched, strict=False) if target in part.keywords
    )


_UNITS = "zero one two three four five six seven eight nine ten eleven twelve thirteen fourteen"
_UNITS += " fifteen sixteen seventeen eighteen nineteen"
UNITS = {w: n for n, w in enumerate(_UNITS.split())}
_TENS = "twenty thirty forty fifty sixty seventy eighty ninety"
TENS = {w: 10 * n for n, w in enumerate(_TENS.split(), 2)}


def numbers_in(said: str) -> list[int]:
    """The numbers in a normalised utterance, in order: digits ("93") or words up to a hundred
    ("ninety three", "a hundred")."""
    numbers: list[int] = []
    words = said.split()
    k = 0
    while k < len(words):
        word = words[k]
        if word.isdigit():
            numbers.append(int(word))
        elif word == "hundred":
            numbers.append(100)
        elif word in TENS:
            unit = UNITS.get(words[k + 1], 0) if k + 1 < len(words) else 0
            numbers.append(TENS[word] + (unit if 0 < unit < 10 else 0))
            k += 1 if 0 < unit < 10 else 0
        elif word in UNITS:
            numbers.append(UNITS[word])
        k += 1
    return numbers


def serial_points(item: Item, said: list[int]) -> int:
    """A point per number that is the previous one said (the start for the first) plus the
    step, counting at most as many as the item's parts."""
    expected = serial_numbers(item)
    step = expected[1] - expected[0]
    previous, points = expected[0] - step, 0
    if said[:1] == [previous]:  # the start said again ("a hundred, ninety-three, ...")
        said = said[1:]
    for number in said[: len(expected)]:
        points += number == previous + step
        previous = number
    return points
