"""What a result must be before CGAmed stores it, beyond its shape (``result_schema.py``): a score
each item allows, a total and a band that add up, a Get Up & Go time its phases add up to; and
what a stored result still waits for (the clinician's score of the items the robot could not
understand)."""

from __future__ import annotations

import json
from typing import Any

from clarc_agents import definitions
from clarc_agents.gug.phases import PHASES, STILL, fall_risk
from clarc_agents.gug.phases import band as gug_band
from clarc_agents.gug.record import UNABLE, UNABLE_BAND
from clarc_sim.exceptions import InvalidResult
from clarc_sim.hospital.result_schema import refusals

TIMED = "get_up_and_go"


def tests_known() -> tuple[str, ...]:
    return definitions.tests() + (TIMED,)


def check_result(result: Any) -> dict[str, Any]:
    """Refuse a result whose numbers do not add up, before it reaches the clinician."""
    if not isinstance(result, dict):
        raise InvalidResult("a result is a JSON object")
    test = result.get("test", "barthel")
    if test not in tests_known():
        raise InvalidResult(f"unknown test {test!r}; the tests are {', '.join(tests_known())}")
    try:  # NaN and Infinity are not JSON: stored, they would break every reader of the store
        json.dumps(result, allow_nan=False)
    except ValueError:
        raise InvalidResult("a number in the result is not finite (NaN or Infinity)") from None
    broken = refusals(result, timed=test == TIMED)
    if broken:
        raise InvalidResult("; ".join(broken))
    if test == TIMED:
        return check_timed_result(result)
    for key in ("patient", "started", "items", "total", "band"):
        if key not in result:
            raise InvalidResult(f"missing {key!r}")
    definition = definitions.load(test)
    items = result["items"]
    if not isinstance(items, list) or [
        i.get("item") if isinstance(i, dict) else None for i in items
    ] != list(definition.order):
        raise InvalidResult(
            f"items must be the {len(definition.items)} {definition.title} items in order: "
            f"{', '.join(definition.order)}"
        )
    for i in items:
        spec = definition.item(i["item"])
        points, via = i.get("points"), i.get("via")
        if points is not None and (isinstance(points, bool) or points not in spec.points):
            raise InvalidResult(f"{i['item']}: {points!r} is not a score of it {spec.points}")
        waiting = spec.needs_clinician and points is None and via is not None
        if via not in spec.via + (None,) or ((points is None) != (via is None) and not waiting):
            raise InvalidResult(
                f"{i['item']}: via must be {' or '.join(spec.via)} for an answer, null otherwise"
            )
    total = sum(i["points"] for i in items if i["points"] is not None)
    band = band_of(definition, items)
    if result["total"] != total or result["band"] != band:
        raise InvalidResult(
            f"total/band {result['total']}/{result['band']} do not match the items ({total}/{band})"
        )
    for key, value in provisional(definition, items).items():
        if key in result and result[key] != value:
            raise InvalidResult(f"{key} {result[key]!r} does not match the items ({value!r})")
    return result


def doubtful(definition, items: list[dict[str, Any]]) -> list[str]:
    """Items the robot could not understand (flagged ``needs_clinician`` though the clinician
    does not score their kind) that wait for the clinician's score."""
    return [
        i["item"]
        for i in items
        if i.get("needs_clinician")
        and i["points"] is None
        and not definition.item(i["item"]).needs_clinician
    ]


def band_of(definition, items: list[dict[str, Any]]) -> str | None:
    """The band of the items' total; none while doubtful items wait (it could be another)."""
    if doubtful(definition, items):
        return None
    return definition.band(sum(i["points"] for i in items if i["points"] is not None))


def provisional(definition, items: list[dict[str, Any]]) -> dict[str, Any]:
    """``provisional`` and the ``total_range`` the doubtful items leave open."""
    total = sum(i["points"] for i in items if i["points"] is not None)
    waiting = doubtful(definition, items)
    open_points = sum(definition.item(k).max for k in waiting)
    return {"provisional": bool(waiting), "total_range": [total, total + open_points]}


def check_timed_result(result: dict[str, Any]) -> dict[str, Any]:
    """A Get Up & Go result: timed (its time, its reaction and phases adding up to it, and the
    band and fall risk of that time) or unable to perform (no time, each void trial's reason)."""
    if result["outcome"] == UNABLE:
        if result["tug_seconds"] is not None or result["phases"] is not None:
            raise InvalidResult("a result unable to perform has no tug_seconds and no phases")
        if result["band"] != UNABLE_BAND or result.get("fall_risk") is not True:
            raise InvalidResult(f"unable to perform is band {UNABLE_BAND!r}, fall_risk true")
        if not result.get("void_reasons"):
            raise InvalidResult("unable to perform needs the reason of each void trial")
        return result
    tug, phases, reaction = result["tug_seconds"], result["phases"], result.get("reaction_seconds")
    if not isinstance(tug, (int, float)) or isinstance(tug, bool) or not tug > 0:
        raise InvalidResult(f"tug_seconds must be a positive number of seconds, got {tug!r}")
    if not isinstance(phases, dict) or list(phases) != [*PHASES, STILL]:
        raise InvalidResult(f"phases must give {', '.join((*PHASES, STILL))} in that order")
    if not isinstance(reaction, (int, float)) or isinstance(reaction, bool):
        raise InvalidResult("a timed result needs reaction_seconds")
    if abs(reaction + sum(phases.values()) - tug) > 0.05:
        raise InvalidResult(
            f"reaction_seconds and the phases add up to {reaction + sum(phases.values()):.2f} s, "
            f"not tug_seconds {tug}"
        )
    if result["band"] != gug_band(tug) or result.get("fall_risk") != fall_risk(tug):
        raise InvalidResult(
            f"band/fall_risk {result['band']}/{result.get('fall_risk')} do not match {tug} s "
            f"({gug_band(tug)}/{fall_risk(tug)})"
        )
    return result


def waiting_for_clinician(definition, items: list[dict[str, Any]]) -> list[str]:
    """The items of a result that wait for the clinician's score."""
    return [
        i["item"]
        for i in items
        if i["points"] is None
        and (definition.item(i["item"]).needs_clinician or i.get("needs_clinician"))
    ]
