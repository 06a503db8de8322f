"""Two hearings that give the same answer, and how sure they make the robot together (pure).

Two hearings whose mistakes are independent are both wrong, and wrong the same way, less often
than either alone: ``1 - (1 - first) * (1 - second)`` bounds the chance that the answer they
agree on is not what was said. Two recognisers on one utterance are such hearings
(asr/second_opinion.py); so are two utterances of one answer, the patient asked again
(``heard_again``): a words or serial answer understood but not sure is asked again (there is no
read-back for them: reading words back would put them in the patient's mouth), and what was
heard each time, with how sure, is kept on the item's node in the DSR (PELEA's
``hearings`` and ``hearing_confidences``), where Speech reads it back at the next answer.

"The same answer" (``same_answer``): understood as the same points for the same parts (a
serial answer's numbers in order, with or without the start said before them; a words answer's
credited words), something credited (two hearings agreeing that nothing was right agree on
nothing).

One voice is misheard the same way twice far more often than independence says: on the speech
benchmark a synthesised voice said again (10% slower, other noise) was heard "Apple, banana,
candy." for "apple, banana, penny" both times (0.31 and 0.33 sure), "A pencil and a laugh."
(0.39, 0.38), "94, 87, 87, 83." for "... 80, 73" (0.36, 0.35). So a hearing counts again only
if it was at least ``FLOOR`` sure on its own: on that benchmark, no answer the repair took was
wrong at 0.4 in any condition, and some were at 0.3 and 0.35 (BENCHMARKS.md section 9b); once
Whisper counted the other spellings of its least sure token (asr/whisper.py), "93, 80, 80, 73."
for "... eighty seven, eighty, seventy three" was heard twice, at 0.40 the first time: 0.45
now. Above ``FLOOR`` the two together always reach Speech's 0.5: the rule is "two hearings,
each at least 0.45 sure, that give the same answer".
"""

from __future__ import annotations

from collections.abc import Iterable

from clarc_agents.definitions import Item
from clarc_agents.questionnaire.answers import serial_start, understand

KINDS = ("words", "serial")  # the kinds with no read-back: asked again instead
FLOOR = 0.45


def same_answer(item: Item, first: str, second: str) -> bool:
    """Whether two transcripts give the same answer to ``item``, something credited (a serial
    answer's numbers in order, the start said before them or not: "100 minus 7 is 93, minus 7
    is 86" and "93, 86" are one answer, as the instrument scores them)."""
    a, b = understand(item, first), understand(item, second)
    given = _given(item, a.matched)
    if a.kind != "answer" or not given:
        return False
    return b.kind == "answer" and (a.points, given) == (b.points, _given(item, b.matched))


def _given(item: Item, matched: tuple[str, ...]) -> tuple[str, ...]:
    """A serial answer's numbers without the start said before them (answers.serial_points)."""
    if item.kind != "serial":
        return matched
    return matched[1:] if matched[:1] == (str(serial_start(item)),) else matched


def independent(*confidences: float) -> float:
    """How sure hearings that agree make the answer, were their mistakes independent."""
    doubt = 1.0
    for confidence in confidences:
        doubt *= 1.0 - confidence
    return 1.0 - doubt


def heard_again(
    item: Item, earlier: Iterable[tuple[str, float]], text: str, confidence: float
) -> tuple[float, str] | None:
    """``text``, heard ``confidence`` sure, against the ``earlier`` hearings of the same item
    (what was heard, how sure): the confidence of the two together and the earlier words, for
    the surest earlier hearing that gives the same answer; None when none does (or either is
    under ``FLOOR``, or the item is not of ``KINDS``)."""
    if item.kind not in KINDS or confidence < FLOOR:
        return None
    agreeing = [
        (seen, before)
        for before, seen in earlier
        if seen >= FLOOR and same_answer(item, text, before)
    ]
    if not agreeing:
        return None
    seen, before = max(agreeing)
    return independent(confidence, seen), before
