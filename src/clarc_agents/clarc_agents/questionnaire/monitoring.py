"""Monitoring of a questionnaire (pure): the deviations of an item (silence, words not
understood, an answer not sure, the person leaving) as facts, so that Decision Support replans
from what really happened."""

from __future__ import annotations

from collections.abc import Iterable

Fact = str


def _without(state: frozenset[Fact], facts: Iterable[Fact]) -> frozenset[Fact]:
    return frozenset(state - set(facts))


ITEM_PROGRESS = (
    "pending",
    "introduced",
    "described",
    "asked",
    "no-answer",
    "not-understood",
    "retry-asked",
    "failed-again",
    "unsure",
    "confirm-asked",
)


def person_lost(state: frozenset[Fact], item: str) -> frozenset[Fact]:
    """The person left: everything waits for them, and the current item starts over when they
    are back (it is introduced again)."""
    state = _without(
        state, {"(person-present)", "(sit-requested)"} | {f"({p} {item})" for p in ITEM_PROGRESS}
    )
    if f"(closed {item})" not in state:
        state |= {f"(pending {item})"}
    return state | {"(person-absent)"}


def window_failed(state: frozenset[Fact], item: str, window: int, outcome: str) -> frozenset[Fact]:
    """An answer window ended without an answer: silence (``no_answer``) or words that were not
    understood (``not_understood``). The first failure leads to a second try; the second, or an
    explicit skip (``skip``), closes the item unanswered."""
    state = _without(state, {f"(asked {item})", f"(retry-asked {item})"})
    if outcome == "skip" or window >= 2:
        return state | {f"(failed-again {item})"}
    return state | {f"({'no-answer' if outcome == 'no_answer' else 'not-understood'} {item})"}


def unsure(state: frozenset[Fact], item: str) -> frozenset[Fact]:
    """An answer heard without enough confidence: it is confirmed before it counts."""
    return _without(state, {f"(asked {item})", f"(retry-asked {item})"}) | {f"(unsure {item})"}


def confirmation_failed(state: frozenset[Fact], item: str, window: int) -> frozenset[Fact]:
    """The patient said no to the answer read back (or nothing): as words not understood in the
    window that heard it."""
    state = _without(state, {f"(confirm-asked {item})", f"(unsure {item})"})
    return window_failed(state, item, window, "not_understood")


def clinician_needed(state: frozenset[Fact]) -> frozenset[Fact]:
    return _without(state, {"(clinician-ok)"}) | {"(clinician-needed)"}


def window_interrupted(state: frozenset[Fact], item: str, window: int) -> frozenset[Fact]:
    """An answer window ended while the agent listening to the patient had been restarted: what
    the patient said or touched meanwhile was lost. Ask again, without counting a failed try:
    the question of the first window, or the options of the second."""
    state = _without(state, {f"(asked {item})", f"(retry-asked {item})"})
    return state | {f"(described {item})" if window == 1 else f"(no-answer {item})"}
