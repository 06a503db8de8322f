"""A questionnaire as a planning problem (pure): the state when Start is pressed, and the PDDL
problem of a test's items in ``data/questionnaire_domain.pddl`` that PELEA's Decision Support
solves."""

from __future__ import annotations

from collections.abc import Iterable

from clarc_agents.definitions import Definition

Fact = str  # "(current feeding)"
GOAL = ("(result-stored)",)


def problem_pddl(state: Iterable[Fact], definition: Definition, goal: Iterable[Fact] = GOAL) -> str:
    items = list(definition.order)
    static = [f"(next {a} {b})" for a, b in zip(items, items[1:], strict=False)] + [
        f"(last {items[-1]})"
    ]
    static += [
        f"({'has-options' if i.kind == 'choose' else 'no-options'} {i.key})"
        for i in definition.items
    ]
    init = sorted(set(state) | set(static))
    return (
        f"(define (problem {definition.test}-run) (:domain questionnaire)\n"
        f"  (:objects {' '.join(items)} - item)\n"
        f"  (:init {' '.join(init)})\n"
        f"  (:goal (and {' '.join(goal)})))\n"
    )


def initial_state(person_present: bool, definition: Definition) -> frozenset[Fact]:
    """The state when the clinician presses Start."""
    items = definition.order
    facts = {"(started)", "(clinician-ok)", f"(current {items[0]})"} | {
        f"(pending {i})" for i in items
    }
    facts.add("(person-present)" if person_present else "(person-absent)")
    return frozenset(facts)
