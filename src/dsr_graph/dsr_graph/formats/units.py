"""Lengths: the DSR holds metres (SI, as REP 103 and every ROS tool), and each file says its unit.

A world or snapshot document declares ``"units": {"length": "m" | "cm" | "mm"}``; its RT
translations are converted to metres once, when it is read, and every document we write says
``"m"``. A document that declares nothing is in millimetres: CORTEX's unit, and that of every
file written before units were declared (so such files still load as they always did).
Angles are radians everywhere. Only RT translations are lengths the DSR itself interprets;
attributes keep the values their writers gave (CORTEX's ``width``/``height`` stay as written).
"""

from __future__ import annotations

import copy
from typing import Any

from dsr_graph.exceptions import FormatError

METRES = "m"
LEGACY = "mm"  # the unit of a document that declares none
PER_METRE = {"m": 1.0, "cm": 100.0, "mm": 1000.0}  # dividing by these gives metres (exactly
# rounded: 2100 / 1000 is 2.1, where 2100 * 0.001 is not)


def declared(doc: dict[str, Any]) -> bool:
    return "units" in doc


def length_unit(doc: dict[str, Any], source: str) -> str:
    """The document's length unit; ``FormatError`` naming what is wrong with its ``units``."""
    units = doc.get("units", {"length": LEGACY})
    if not isinstance(units, dict) or set(units) != {"length"}:
        raise FormatError(
            f'{source}: "units" must be {{"length": "m" | "cm" | "mm"}}, got {units!r}'
        )
    unit = units["length"]
    if unit not in PER_METRE:
        raise FormatError(
            f'{source}: "units.length" must be one of {sorted(PER_METRE)}, got {unit!r}'
        )
    return unit


def scale_rt(spec: Any, per_metre: float) -> Any:
    """An RT spec (``matrix`` or ``translation`` + rotation) with its translation in metres. A
    malformed spec is returned as it is, for the reader to report."""
    if per_metre == 1.0 or not isinstance(spec, dict):
        return spec
    try:
        if "matrix" in spec:
            matrix = copy.deepcopy(spec["matrix"])
            for row in range(3):
                matrix[row][3] = matrix[row][3] / per_metre
            return {**spec, "matrix": matrix}
        if "translation" in spec:
            return {**spec, "translation": [v / per_metre for v in spec["translation"]]}
    except (TypeError, IndexError, KeyError):
        pass
    return spec


def in_metres(doc: dict[str, Any], source: str) -> dict[str, Any]:
    """The document with its RT translations in metres (itself when they already are)."""
    per_metre = PER_METRE[length_unit(doc, source)]
    if per_metre == 1.0:
        return doc
    converted = {**doc, "units": {"length": METRES}}
    if isinstance(doc.get("edges"), list):
        converted["edges"] = [
            {**e, "rt": scale_rt(e["rt"], per_metre)} if isinstance(e, dict) and "rt" in e else e
            for e in doc["edges"]
        ]
    return converted


def delta_in_metres(delta: dict[str, Any], per_metre: float) -> dict[str, Any]:
    """A journaled delta of a state written in another unit, its RT operations in metres."""
    if per_metre == 1.0:
        return delta
    ops = [
        {**op, "rt": scale_rt(op["rt"], per_metre)} if isinstance(op, dict) and "rt" in op else op
        for op in delta.get("ops", [])
    ]
    return {**delta, "ops": ops}
