"""PELEA's Decision Support: a plan from the current state to the goal, by a real automated
planner (pyperplan: greedy best-first search with the FF heuristic) on the PDDL domain of the
test (``data/questionnaire_domain.pddl`` for every questionnaire test: the items, their order and
whether they have options come from the test's definition, in the problem). Pure; no ROS."""

from __future__ import annotations

import functools
import os
import tempfile
from collections.abc import Iterable
from dataclasses import dataclass
from importlib import resources

from pyperplan import grounding, search
from pyperplan.heuristics.relaxation import hFFHeuristic
from pyperplan.pddl.parser import Parser

from clarc_agents.exceptions import NoPlan

Fact = str  # "(current feeding)"


PLANS_KEPT = 512  # plans remembered by their problem's text (each a few kB)


@dataclass(frozen=True)
class Step:
    """One grounded action of a plan, with what it is expected to change."""

    name: str  # "introduce"
    args: tuple[str, ...]  # ("feeding",)
    add: frozenset[Fact]
    delete: frozenset[Fact]

    def __str__(self) -> str:
        return "(" + " ".join((self.name,) + self.args) + ")"

    def apply(self, state: frozenset[Fact]) -> frozenset[Fact]:
        return (state - self.delete) | self.add


def domain_path(name: str) -> str:
    """The PDDL domain of a test kind, shipped in ``clarc_agents/data``."""
    return str(resources.files("clarc_agents").joinpath(f"data/{name}_domain.pddl"))


def solve(domain: str, problem: str, state: Iterable[Fact], goal: Iterable[Fact]) -> list[Step]:
    """The plan pyperplan finds for ``problem`` (PDDL text) in the ``domain`` file."""
    steps = _plan(domain, problem)
    if steps is None:
        raise NoPlan(f"no plan reaches {list(goal)} from {sorted(state)}")
    return list(steps)


@functools.lru_cache(maxsize=PLANS_KEPT)
def _plan(domain: str, problem: str) -> tuple[Step, ...] | None:
    """The search itself, deterministic: the same problem (a replan from a state met before,
    a PELEA restarted where it was) is not searched again."""
    fd, problem_file = tempfile.mkstemp(suffix=".pddl", prefix="pelea-problem-")
    try:
        with os.fdopen(fd, "w") as f:
            f.write(problem)
        parser = Parser(domain, problem_file)
        parsed = parser.parse_problem(parser.parse_domain())
    finally:
        os.unlink(problem_file)
    task = grounding.ground(parsed)
    solution: list | None = search.greedy_best_first_search(task, hFFHeuristic(task))
    if solution is None:
        return None
    steps = []
    for op in solution:
        name, *args = op.name.strip("()").split()
        steps.append(Step(name, tuple(args), frozenset(op.add_effects), frozenset(op.del_effects)))
    return tuple(steps)
