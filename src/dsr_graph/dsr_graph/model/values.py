"""Attribute value types: the names used in vocabulary files and how a JSON value is checked.

JSON does not tell 2 from 2.0 reliably, so the vocabulary declares each attribute's type and
``coerce`` turns an incoming JSON value into the canonical Python value for that type (an int
given for a float is widened; nothing is ever narrowed or guessed).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

from dsr_graph.exceptions import ValueTypeError
from dsr_graph.model.binary import ARRAYS, BYTES, array_coercer, coerce_bytes

UINT32_MAX = 2**32 - 1
UINT64_MAX = 2**64 - 1


def _is_int(value: Any) -> bool:
    return isinstance(value, int) and not isinstance(value, bool)


def _is_number(value: Any) -> bool:
    return (_is_int(value) or isinstance(value, float)) and not isinstance(value, bool)


def _finite_float(value: Any, what: str = "value") -> float:
    if not _is_number(value):
        raise ValueTypeError(f"{what} must be a number, got {type(value).__name__} {value!r}")
    result = float(value)
    if not math.isfinite(result):
        raise ValueTypeError(f"{what} must be finite, got {value!r}")
    return result


def _bool(value: Any) -> bool:
    if not isinstance(value, bool):
        raise ValueTypeError(f"expected true or false, got {type(value).__name__} {value!r}")
    return value


def _int_in(lo: int, hi: int) -> Callable[[Any], int]:
    def check(value: Any) -> int:
        # CORTEX writes uint64 as decimal strings; accept those, nothing else textual.
        if isinstance(value, str) and value.strip().isdigit():
            value = int(value)
        if not _is_int(value):
            raise ValueTypeError(f"expected an integer, got {type(value).__name__} {value!r}")
        if not lo <= value <= hi:
            raise ValueTypeError(f"integer {value} is outside [{lo}, {hi}]")
        return value

    return check


def _string(value: Any) -> str:
    if not isinstance(value, str):
        raise ValueTypeError(f"expected a string, got {type(value).__name__} {value!r}")
    return value


def _list(value: Any) -> list:
    if not isinstance(value, (list, tuple)):
        raise ValueTypeError(f"expected a list, got {type(value).__name__} {value!r}")
    return list(value)


def _float_vector(value: Any) -> list:
    items = _list(value)
    if all(type(v) is float for v in items) and all(map(math.isfinite, items)):
        return items  # the common case (sensor rows), checked without a call per element
    return [_finite_float(v, f"element {i}") for i, v in enumerate(items)]


def _byte_vector(value: Any) -> list:
    items = _list(value)
    for i, v in enumerate(items):
        if not _is_int(v) or not 0 <= v <= 255:
            raise ValueTypeError(f"element {i} must be a byte (0..255), got {v!r}")
    return items


def _string_vector(value: Any) -> list:
    items = _list(value)
    for i, v in enumerate(items):
        if not isinstance(v, str):
            raise ValueTypeError(f"element {i} must be a string, got {v!r}")
    return items


def _float_matrix(value: Any) -> list:
    rows = [_float_vector(row) for row in _list(value)]
    if rows and any(len(row) != len(rows[0]) for row in rows):
        raise ValueTypeError("matrix rows must all have the same length")
    return rows


COERCERS: dict[str, Callable[[Any], Any]] = {
    "bool": _bool,
    "int": _int_in(-(2**63), 2**63 - 1),
    "uint": _int_in(0, UINT32_MAX),
    "uint64": _int_in(0, UINT64_MAX),
    "float": lambda v: _finite_float(v),
    "string": _string,
    "float_vector": _float_vector,
    "byte_vector": _byte_vector,
    "string_vector": _string_vector,
    "float_matrix": _float_matrix,
    BYTES: coerce_bytes,  # binary values (binary.py): base64 in JSON
    **{name: array_coercer(name) for name in ARRAYS},
}

VALUE_TYPES = tuple(COERCERS)
BINARY = frozenset({BYTES, *ARRAYS})  # types whose values are bytes, not JSON


def coerce(type_name: str, value: Any) -> Any:
    """Return ``value`` in the canonical form of ``type_name`` or raise ``ValueTypeError``."""
    try:
        coercer = COERCERS[type_name]
    except KeyError:
        raise ValueTypeError(f"unknown value type {type_name!r}") from None
    return coercer(value)
