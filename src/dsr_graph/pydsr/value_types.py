"""Which Python values an attribute takes, as CORTEX's pydsr decides (python_api.cpp's variant
and its typed attribute map; its tests, VariantCastTest.py, say it case by case). Pure.

A value has a *kind* (what Python shows: an int, a list of floats, a uint8 array, ...). An
attribute named in the registry has a *type*, from the DSR's vocabulary (which holds CORTEX's
attribute registry) or, for CORTEX's C++-only shapes, from ``CORTEX_SHAPES``; a value goes into
such an attribute only if its kind fits the type (no narrowing, no guessing: 1 is not a float,
[10, 11] is not a float vector, 256 is not a byte). An attribute of no known name keeps the
family of its first value.
"""

from __future__ import annotations

from functools import cache
from typing import Any

import numpy as np

from dsr_graph.model.vocabulary import Vocabulary

# CORTEX's attribute types the vocabulary has no type for: fixed-size float vectors and vectors
# of uint64 (dsr_attr_name.h)
CORTEX_SHAPES: dict[str, tuple[str, int | None]] = {
    "test_vec2_type": ("vec_float", 2),
    "test_vec3_type": ("vec_float", 3),
    "test_vec4_type": ("vec_float", 4),
    "test_vec6_type": ("vec_float", 6),
    "rt_timestamps": ("vec_u64", None),
    "test_uint64_vec_type": ("vec_u64", None),
}
FROM_VOCABULARY = {
    "int": "int",
    "float": "float",
    "bool": "bool",
    "string": "string",
    "uint": "uint32",
    "uint64": "uint64",
    "float_vector": "vec_float",
    "byte_vector": "vec_byte",
    "bytes": "binary",
    "uint8_array": "binary",
    "uint16_array": "binary",
    "float32_array": "binary",
    "string_vector": "strings",
    "float_matrix": "matrix",
}
# kinds that stand for one another in an attribute of no known type
FAMILIES = {
    "float_list": "floats",
    "float_array": "floats",
    "int_list": "integers",
    "u8_array": "integers",
    "u64_array": "integers",
    "int_array": "integers",
    "bytes": "integers",
}


def kind_of(value: Any) -> str:
    """The kind of a Python value; TypeError for one no attribute can hold."""
    if isinstance(value, (bool, np.bool_)):
        return "bool"
    if isinstance(value, str):
        return "string"
    if isinstance(value, (int, np.integer)):
        return "int"
    if isinstance(value, (float, np.floating)):
        return "float"
    if isinstance(value, (bytes, bytearray)):
        return "bytes"
    if isinstance(value, np.ndarray):
        if value.dtype == np.uint8:
            return "u8_array"
        if value.dtype == np.uint64:
            return "u64_array"
        if np.issubdtype(value.dtype, np.integer):
            return "int_array"
        if np.issubdtype(value.dtype, np.floating):
            return "float_array"
    elif isinstance(value, (list, tuple)):
        if value and all(isinstance(v, str) for v in value):
            return "string_list"
        if value and all(isinstance(v, (list, tuple)) for v in value):
            if all(kind_of(row) in ("float_list", "int_list") for row in value):
                return "matrix"
        numbers = [isinstance(v, (int, float, np.number)) for v in value]
        if all(numbers):
            ints = all(
                isinstance(v, (int, np.integer)) and not isinstance(v, (bool, np.bool_))
                for v in value
            )
            return "int_list" if ints and value else "float_list"
    raise TypeError(
        "an attribute holds a str, bool, int, float, a list or numpy array of numbers, or "
        f"bytes; got {type(value).__name__} {str(value)[:40]}"
    )


@cache
def _vocabulary() -> Vocabulary:
    return Vocabulary.default()


def declared_type(name: str) -> tuple[str, int | None] | None:
    """(type, fixed length) of an attribute named ``name``; None for a name of no known type."""
    if name in CORTEX_SHAPES:
        return CORTEX_SHAPES[name]
    vocabulary_type = _vocabulary().attribute_type(name)
    if vocabulary_type in FROM_VOCABULARY:
        return FROM_VOCABULARY[vocabulary_type], None
    return None


def accepts(declared: tuple[str, int | None], kind: str, value: Any) -> bool:
    """Whether a value of this kind goes into an attribute of this type."""
    type_name, length = declared
    if type_name in ("string", "int", "float", "bool"):
        return kind == type_name
    if type_name == "uint32":
        return kind == "int" and 0 <= int(value) <= 2**32 - 1
    if type_name == "uint64":
        return kind == "int" and 0 <= int(value) <= 2**64 - 1
    if type_name == "vec_float":
        return kind in ("float_list", "float_array") and (length is None or len(value) == length)
    if type_name == "vec_byte":
        if kind == "int_list":
            return all(0 <= v <= 255 for v in value)
        return kind in ("u8_array", "bytes")
    if type_name == "vec_u64":
        return (kind == "int_list" and all(v >= 0 for v in value)) or kind == "u64_array"
    if type_name == "binary":
        return kind in ("u8_array", "u64_array", "int_array", "float_array", "bytes", "int_list")
    if type_name == "strings":
        return kind == "string_list"
    if type_name == "matrix":
        return kind == "matrix"
    return False


def same_family(a: str, b: str) -> bool:
    return a == b or (a in FAMILIES and FAMILIES.get(a) == FAMILIES.get(b))


def stored(value: Any, kind: str, declared: tuple[str, int | None] | None) -> Any:
    """The value as ``Attribute.value`` gives it back: vectors as numpy arrays (float32 for
    floats, uint8 for bytes, uint64 for CORTEX's u64 vectors), scalars as Python's own."""
    type_name = declared[0] if declared else None
    if type_name == "vec_float" or (type_name is None and kind == "float_list"):
        return np.asarray(value, dtype=np.float32)
    if type_name == "vec_byte" or (type_name is None and kind == "int_list" and _bytes(value)):
        if kind == "bytes":
            return np.frombuffer(bytes(value), dtype=np.uint8).copy()
        return np.asarray(value, dtype=np.uint8)
    if type_name == "vec_u64" or (type_name is None and kind == "int_list"):
        return np.asarray(value, dtype=np.uint64)
    if kind == "bytes":
        return np.frombuffer(bytes(value), dtype=np.uint8).copy()
    if kind == "int":
        return int(value)
    if kind == "float":
        return float(value)
    if kind == "bool":
        return bool(value)
    if kind in ("string_list", "matrix"):
        return [list(v) if isinstance(v, tuple) else v for v in value]
    return value


def _bytes(values: Any) -> bool:
    return all(0 <= v <= 255 for v in values)


def describe(declared: tuple[str, int | None]) -> str:
    type_name, length = declared
    return f"{type_name}[{length}]" if length else type_name
