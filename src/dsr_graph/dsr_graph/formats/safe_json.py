"""The one JSON reader for everything that arrives from outside a process: every topic, service,
request and file of the suite reads JSON through ``loads`` (orjson underneath).

Anything a hostile or broken sender can make is a ``JsonRefused`` (a ``ValueError``) naming what
is wrong, never another exception: more than ``max_bytes`` UTF-8 bytes, nesting deeper than
``max_depth`` (Python code that walks a document recurses, so depth is bounded before any of it
runs), NaN or Infinity (not JSON; orjson refuses them, and numbers too large for a double), and
integers outside a signed 64-bit range (orjson would silently turn them into floats, and nothing
in the DSR can hold them: ROS messages, SQLite and our value types all stop at 64 bits).
"""

from __future__ import annotations

import json
import math
from typing import Any

import orjson

from dsr_graph.exceptions import JsonRefused

DEFAULT_MAX_BYTES = 4 * 1024 * 1024  # a request, a device message (the server's is a parameter)
# what a reader of a message raises when it does not have the shape it reads
READING_ERRORS = (ValueError, KeyError, TypeError, AttributeError, IndexError)
MAX_DEPTH = 64  # deepest nesting accepted: our formats need about 8
INT_MIN, INT_MAX = -(2**63), 2**63 - 1
TWO_63 = float(2**63)


def loads(
    data: str | bytes,
    max_bytes: int | None = DEFAULT_MAX_BYTES,
    max_depth: int = MAX_DEPTH,
    walk: bool = True,
):
    """The value of a JSON text, or ``JsonRefused``. ``max_bytes`` counts UTF-8 bytes (None: no
    limit, for trusted local files whose size the caller bounds otherwise). ``walk=False``: the
    value is not walked for depth and 64-bit integers (orjson's own limits remain: nesting up
    to 1024, no NaN or Infinity), only for a whole snapshot from the DSR server, which a replica
    restores without checking its elements anyway (a walk of a 100k-node one took 0.17 s)."""
    if isinstance(data, str):  # orjson reads a str as it is (a lone surrogate is refused)
        raw = data if max_bytes is None else data.encode("utf-8", "surrogatepass")
    else:
        raw = bytes(data)
    if max_bytes is not None and len(raw) > max_bytes:
        raise JsonRefused(f"{len(raw)} bytes exceeds the limit of {max_bytes}")
    try:
        doc = orjson.loads(raw)
    except orjson.JSONDecodeError as e:
        raise JsonRefused(f"not JSON: {e}") from None
    if walk:
        _check(doc, raw, max_depth)
    return doc


def loads_object(
    data: str | bytes, max_bytes: int | None = DEFAULT_MAX_BYTES, walk: bool = True
) -> dict[str, Any]:
    """``loads`` of a text that must be a JSON object."""
    doc = loads(data, max_bytes, walk=walk)
    if not isinstance(doc, dict):
        raise JsonRefused(f"a JSON object was expected, got {_kind(doc)}")
    return doc


def _check(doc: Any, raw: bytes, max_depth: int) -> None:
    """Depth and integer range, without recursion: a walk of the containers one level at a
    time, with no call per value (a 14 MB snapshot has about two million of them)."""
    suspicious = False
    level = [doc] if type(doc) in (dict, list) else []
    if not level:
        suspicious = _out_of_range(doc)
    depth = 0
    while level:
        depth += 1
        if depth > max_depth:
            raise JsonRefused(f"nested deeper than {max_depth} levels")
        below = []
        for value in level:
            for item in value.values() if type(value) is dict else value:
                kind = type(item)
                if kind is dict or kind is list:
                    below.append(item)
                elif kind is int:
                    suspicious = suspicious or not INT_MIN <= item <= INT_MAX
                elif kind is float:
                    suspicious = suspicious or not -TWO_63 < item < TWO_63
        level = below
    if suspicious:
        # orjson reads an integer literal beyond 64 bits as a float (or, up to 2**64, as an
        # int): tell it from 1e30 by reading the (depth-checked) text again, integers exact
        json.loads(raw, parse_int=_bounded_int)


def _out_of_range(value: Any) -> bool:
    """An int beyond int64, or a float as large as one that may have been such an int."""
    kind = type(value)
    if kind is int:
        return not INT_MIN <= value <= INT_MAX
    return kind is float and math.isfinite(value) and abs(value) >= TWO_63


def _bounded_int(literal: str) -> int:
    if len(literal) > 20 or not INT_MIN <= int(literal) <= INT_MAX:
        raise JsonRefused(f"integer {literal[:40]} is outside the 64-bit range")
    return int(literal)


def _kind(doc: Any) -> str:
    return {dict: "an object", list: "an array", str: "a string", bool: "a boolean"}.get(
        type(doc), "null" if doc is None else "a number"
    )
