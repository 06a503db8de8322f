"""Monitoring: the high-level state of the test and the facts that record deviations, so that
Decision Support replans from what really happened (pure)."""

from __future__ import annotations

from collections.abc import Iterable

from clarc_agents.pelea.decision_support import Fact


def _without(state: frozenset[Fact], facts: Iterable[Fact]) -> frozenset[Fact]:
    return frozenset(state - set(facts))


def person_back(state: frozenset[Fact]) -> frozenset[Fact]:
    return _without(state, {"(person-absent)", "(sit-requested)"}) | {"(person-present)"}
