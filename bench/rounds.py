"""Ratios a noisy machine cannot fake: both sides of a ratio sampled in interleaved rounds of one
run (A, B, then B, A, ...), a ratio taken per round, and the median of those ratios reported with
their spread. A neighbour's burst lands on both sides of the round it falls in; consecutive runs
of the same code moved a raw baseline from 0.49 to 0.88 ms, which no single-run ratio survives."""

from __future__ import annotations

import statistics
from collections.abc import Callable
from typing import Any

from harness import percentiles

Side = Callable[[int], list[float]]  # samples (seconds) of one round, given the round's index


def interleave(sides: dict[str, Side], rounds: int) -> dict[str, list[list[float]]]:
    """Each side's samples, round by round: a round runs every side once, in the order given on
    even rounds and reversed on odd ones, so a drift across the run favours no side."""
    names = list(sides)
    taken: dict[str, list[list[float]]] = {name: [] for name in names}
    for r in range(rounds):
        for name in names if r % 2 == 0 else names[::-1]:
            taken[name].append(sides[name](r))
    return taken


def pooled(rounds: list[list[float]]) -> dict[str, float]:
    """The percentiles of every round's samples together (the figures bench.json always had)."""
    return percentiles([x for samples in rounds for x in samples])


def ratio(
    numerator: list[list[float]], denominator: list[list[float]], stat: str
) -> dict[str, Any]:
    """``stat`` ("p50_ms", "p99_ms", ...) of each round's numerator over its denominator: the
    median with the spread (min, quartiles, max) and every round's ratio."""
    per_round = [
        percentiles(a)[stat] / percentiles(b)[stat]
        for a, b in zip(numerator, denominator, strict=True)
    ]
    return summary(per_round) | {"stat": stat}


def summary(per_round: list[float]) -> dict[str, Any]:
    """The median of per-round ratios, their spread and the rounds themselves."""
    q1, _, q3 = (
        statistics.quantiles(per_round, n=4, method="inclusive")
        if len(per_round) > 1
        else per_round * 3
    )
    return {
        "median": statistics.median(per_round),
        "spread": {"min": min(per_round), "q1": q1, "q3": q3, "max": max(per_round)},
        "rounds": per_round,
    }


def shown(r: dict[str, Any]) -> str:
    """A ratio as the table prints it: median x, interquartile and full range, rounds."""
    s = r["spread"]
    return (
        f"x{r['median']:.2f} (quartiles {s['q1']:.2f}-{s['q3']:.2f}, range {s['min']:.2f}-"
        f"{s['max']:.2f}, {len(r['rounds'])} rounds)"
    )
