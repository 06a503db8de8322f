"""The shape of a result that CGAmed accepts on ``clarc/cgamed/store_result``, as JSON Schema
(checked with jsonschema before anything else reads it): every field a test's result carries,
its type and its bounds, and nothing else. What the numbers mean (a score the item allows, a
total that adds up, a band that matches) is checked after it, in ``result_checks.check_result``.
"""

from __future__ import annotations

from typing import Any

from jsonschema import Draft202012Validator

NAME = {"type": "string", "minLength": 1, "maxLength": 200, "pattern": r"\S"}
TIME = {"type": "string", "minLength": 1, "maxLength": 64}
COUNT = {"type": "integer", "minimum": 0, "maximum": 1_000_000}
SECONDS = {"type": "number", "minimum": 0, "maximum": 3600}

COMMON = {
    "test": {"type": "string", "pattern": "^[a-z][a-z0-9_]{0,63}$"},
    "patient": NAME,
    "patient_id": {"type": "integer", "minimum": 1, "maximum": 2**63 - 1},
    "started": TIME,
    "finished": {"anyOf": [TIME, {"type": "null"}]},
    "band": {"type": "string", "maxLength": 100},
    "clinician_called": {"type": "boolean"},
    "person_lost": {"type": "boolean"},
    "person_lost_count": COUNT,
}

ITEM = {
    "type": "object",
    "required": ["item", "points", "via", "attempts"],
    "additionalProperties": False,
    "properties": {
        "item": {"type": "string", "maxLength": 100},
        "points": {"type": ["integer", "null"], "minimum": 0, "maximum": 1000},
        "via": {"type": ["string", "null"], "maxLength": 20},
        "attempts": COUNT,
        "max": COUNT,
        "needs_clinician": {"type": "boolean"},
        "answer": {"type": "string", "maxLength": 10_000},
        "drawing": {"type": "string", "maxLength": 1_000_000},  # SVG path data
        "heard": {"type": "string", "maxLength": 10_000},  # what was not understood
        # the clips of what was said to it (paths on the robot), the clinician's evidence
        "audio": {"type": "array", "maxItems": 50, "items": {"type": "string", "maxLength": 4096}},
    },
}

QUESTIONNAIRE = {
    "type": "object",
    "required": ["patient", "started", "items", "total", "band"],
    "additionalProperties": False,
    "properties": {
        **COMMON,
        "total": {"type": "integer", "minimum": 0, "maximum": 100_000},
        "max_total": COUNT,
        # null while items the robot could not understand wait for the clinician
        "band": {"type": ["string", "null"], "maxLength": 100},
        "provisional": {"type": "boolean"},
        "total_range": {
            "type": "array",
            "minItems": 2,
            "maxItems": 2,
            "items": {"type": "integer", "minimum": 0, "maximum": 100_000},
        },
        "complete": {"type": "boolean"},
        "items": {"type": "array", "maxItems": 200, "items": ITEM},
        "unanswered": {
            "type": "array",
            "maxItems": 200,
            "items": {"type": "string", "maxLength": 100},
        },
    },
}

TIMED = {
    "type": "object",
    "required": ["test", "patient", "started", "outcome", "tug_seconds", "phases", "band"],
    "additionalProperties": False,
    "properties": {
        **COMMON,
        "outcome": {"enum": ["timed", "unable"]},
        "tug_seconds": {"anyOf": [SECONDS, {"type": "null"}]},
        "reaction_seconds": {"anyOf": [SECONDS, {"type": "null"}]},
        "phases": {
            "anyOf": [
                {"type": "object", "maxProperties": 20, "additionalProperties": SECONDS},
                {"type": "null"},
            ]
        },
        "fall_risk": {"type": "boolean"},
        "trials": {"type": "integer", "minimum": 0, "maximum": 100},
        "void_reasons": {
            "type": "array",
            "maxItems": 100,
            "items": {"type": "string", "maxLength": 1000},
        },
    },
}

_VALIDATORS = {
    kind: Draft202012Validator(schema) for kind, schema in (("q", QUESTIONNAIRE), ("t", TIMED))
}
MAX_SHOWN = 200  # characters of one refusal


def refusals(result: Any, timed: bool) -> list[str]:
    """Every way ``result`` breaks its schema, each naming the field (empty: it fits)."""
    validator = _VALIDATORS["t" if timed else "q"]
    found = []
    for error in sorted(validator.iter_errors(result), key=lambda e: list(map(str, e.path))):
        where = "".join(f"[{p}]" if isinstance(p, int) else f".{p}" for p in error.path)
        message = error.message
        if len(message) > MAX_SHOWN:
            message = message[:MAX_SHOWN] + "..."
        found.append(f"{'result' + where}: {message}")
    return found
