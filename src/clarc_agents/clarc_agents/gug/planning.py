"""The Get Up & Go as a planning problem (pure): the state when Start is pressed and the PDDL
problem in ``data/gug_domain.pddl`` that PELEA's Decision Support solves."""

from __future__ import annotations

GOAL = ("(said-goodbye)",)


def problem_pddl(state: frozenset[str]) -> str:
    return (
        "(define (problem gug-run) (:domain get-up-and-go)\n"
        f"  (:init {' '.join(sorted(state))})\n"
        f"  (:goal (and {' '.join(GOAL)})))\n"
    )


def initial_state(person_present: bool) -> frozenset[str]:
    present = "(person-present)" if person_present else "(person-absent)"
    return frozenset({"(started)", "(unexplained)", "(trials-left)", present})
