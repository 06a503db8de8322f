"""Binary attribute values: raw bytes, and typed numeric arrays with a shape (a camera's RGB and
depth images, embeddings) (pure).

In the graph a ``bytes`` value is a Python ``bytes``; an array value is a read-only, C-ordered
``numpy.ndarray`` of its declared element type. In JSON (world files, snapshots, the journal) a
value is an object that says what it is, the bytes in base64:

    {"$bytes": "aGVsbG8="}
    {"$array": "AAEC...", "dtype": "uint8", "shape": [480, 640, 3]}

Array element types are fixed-size and little-endian, whatever the machine: ``uint8``,
``uint16`` (a depth image in millimetres) and ``float32``. A list of bytes (0..255), as CORTEX's
files hold a camera's ``cam_rgb``, is taken as the value's bytes (an array of one dimension).
Large values travel beside the JSON on the wire (``protocol/blobs.py``): a replica that has not
had their bytes holds a ``BlobRef``.
"""

from __future__ import annotations

import base64
import binascii
import json
import math
from typing import Any

import numpy as np
import orjson

from dsr_graph.exceptions import ValueTypeError

BYTES = "bytes"
# vocabulary type -> (element type name in JSON, numpy dtype)
ARRAYS = {
    "uint8_array": ("uint8", np.dtype("u1")),
    "uint16_array": ("uint16", np.dtype("<u2")),
    "float32_array": ("float32", np.dtype("<f4")),
}
ELEMENT_OF = {dtype: element for element, dtype in ARRAYS.values()}  # numpy dtype -> JSON name
ITEMSIZE_OF = {element: dtype.itemsize for element, dtype in ARRAYS.values()}
MAX_DIMENSIONS = 8


class BlobRef:
    """A binary value a replica knows by its digest only: its bytes travel beside the delta
    (``protocol/blobs.py``) and did not reach this replica (fetched with dsr/get_blob).
    ``dtype``: "bytes" or an array element type; ``shape``: an array's (None for bytes); ``at``:
    for sensor data, the name of the node that wrote it, which alone holds the bytes (the
    server never receives them: they are fetched with that node's dsr/get_blob/<name>)."""

    __slots__ = ("digest", "dtype", "shape", "size", "at")

    def __init__(
        self,
        digest: str,
        dtype: str,
        shape: tuple[int, ...] | None,
        size: int,
        at: str | None = None,
    ):
        self.digest, self.dtype, self.shape, self.size, self.at = digest, dtype, shape, size, at

    def to_json(self) -> dict[str, Any]:
        # "at" first: the server tells a sensor blob from the text, before parsing it
        doc: dict[str, Any] = {} if self.at is None else {"at": self.at}
        doc.update({"$blob": self.digest, "dtype": self.dtype, "size": self.size})
        if self.shape is not None:
            doc["shape"] = list(self.shape)
        return doc

    def __eq__(self, other: object) -> bool:
        return isinstance(other, BlobRef) and self.digest == other.digest

    def __hash__(self) -> int:
        return hash(self.digest)

    def __repr__(self) -> str:
        return f"BlobRef({self.digest[:19]}..., {self.dtype}, {self.shape}, {self.size})"


def _decoded(text: Any, what: str) -> bytes:
    if not isinstance(text, str):
        raise ValueTypeError(f"{what} must be base64 text, got {type(text).__name__}")
    try:
        return base64.b64decode(text, validate=True)
    except (binascii.Error, ValueError):
        raise ValueTypeError(f"{what} is not valid base64") from None


def coerce_bytes(value: Any) -> bytes:
    """``bytes`` from bytes (or a bytearray, a memoryview) or {"$bytes": base64}."""
    if isinstance(value, (bytes, bytearray, memoryview)):
        return bytes(value)
    if isinstance(value, BlobRef) and value.dtype == BYTES:
        return value  # a replica's value not fetched yet
    if isinstance(value, list):  # a byte vector (CORTEX files)
        return _byte_list(value, "bytes")
    if isinstance(value, dict) and set(value) == {"$bytes"}:
        return _decoded(value["$bytes"], '"$bytes"')
    raise ValueTypeError(
        f'expected bytes ({{"$bytes": base64}} in JSON), got {type(value).__name__} {_short(value)}'
    )


def array_coercer(type_name: str):
    """The coercer of an array type: a numpy array of its element type (any shape), or its JSON
    object; the result is read-only, so a value in the graph cannot change under it."""
    element, dtype = ARRAYS[type_name]

    def check(value: Any) -> np.ndarray:
        if isinstance(value, BlobRef):
            if value.dtype != element:
                raise ValueTypeError(f"expected an array of {element}, got {value.dtype!r}")
            return value  # a replica's value not fetched yet
        if isinstance(value, np.ndarray):
            if value.dtype.kind != dtype.kind or value.dtype.itemsize != dtype.itemsize:
                raise ValueTypeError(f"expected an array of {element}, got {value.dtype}")
            # little-endian, C order; a caller's writable array is copied, never shared
            copy = True if value.flags.writeable else None
            array = np.array(value, dtype=dtype, order="C", copy=copy)
        elif isinstance(value, list):  # a byte vector of the array's bytes (CORTEX files)
            data = _byte_list(value, element)
            if len(data) % dtype.itemsize:
                raise ValueTypeError(
                    f"{len(data)} bytes are not a whole number of {element} ({dtype.itemsize} each)"
                )
            array = np.frombuffer(data, dtype=dtype)
        elif isinstance(value, dict) and set(value) == {"$array", "dtype", "shape"}:
            if value["dtype"] != element:
                raise ValueTypeError(f"expected an array of {element}, got {value['dtype']!r}")
            shape = _shape(value["shape"])
            data = _decoded(value["$array"], '"$array"')
            expected = math.prod(shape) * dtype.itemsize
            if len(data) != expected:
                raise ValueTypeError(
                    f"an array of shape {list(shape)} of {element} has {expected} bytes, "
                    f"got {len(data)}"
                )
            array = np.frombuffer(data, dtype=dtype).reshape(shape)
        else:
            raise ValueTypeError(
                f'expected an array of {element} ({{"$array": base64, "dtype": "{element}", '
                f'"shape": [...]}} in JSON), got {type(value).__name__} {_short(value)}'
            )
        if array.ndim == 0:
            raise ValueTypeError("an array needs at least one dimension")
        if array.dtype.kind == "f" and not np.isfinite(array).all():
            raise ValueTypeError(f"an array of {element} must hold finite numbers only")
        array.flags.writeable = False
        return array

    return check


def _byte_list(value: list, element: str) -> bytes:
    if not all(isinstance(v, int) and not isinstance(v, bool) and 0 <= v <= 255 for v in value):
        raise ValueTypeError(f"a list given for an array of {element} must hold bytes (0..255)")
    return bytes(value)


def _shape(value: Any) -> tuple[int, ...]:
    if (
        not isinstance(value, list)
        or not 1 <= len(value) <= MAX_DIMENSIONS
        or not all(isinstance(n, int) and not isinstance(n, bool) and n >= 0 for n in value)
    ):
        raise ValueTypeError(
            f'"shape" must be a list of 1 to {MAX_DIMENSIONS} sizes (integers >= 0), '
            f"got {_short(value)}"
        )
    return tuple(value)


def _short(value: Any) -> str:
    text = repr(value)
    return text if len(text) <= 60 else text[:57] + "..."


def is_binary(value: Any) -> bool:
    return isinstance(value, (bytes, np.ndarray, BlobRef))


def size_of(value: Any) -> int:
    """Bytes a binary value holds (0 for any other value)."""
    if isinstance(value, bytes):
        return len(value)
    if isinstance(value, np.ndarray):
        return int(value.nbytes)
    if isinstance(value, BlobRef):
        return value.size
    return 0


def declared_size(value: Any) -> int:
    """Bytes a value as a request gives it would hold once read (0: not a binary value), known
    before it is decoded, so an oversized one is refused without building it."""
    if isinstance(value, dict):
        if isinstance(value.get("$bytes"), str):
            return len(value["$bytes"]) * 3 // 4
        if isinstance(value.get("$array"), str):
            itemsize = ITEMSIZE_OF.get(value.get("dtype"), 1)
            shape = value.get("shape")
            if isinstance(shape, list) and all(isinstance(n, int) for n in shape):
                return math.prod(shape) * itemsize
            return len(value["$array"]) * 3 // 4
    return size_of(value)


def to_json_value(value: Any) -> Any:
    """A binary value as its JSON object (TypeError for anything else): the ``default`` of a JSON
    encoder (``json.dumps(doc, default=to_json_value)``)."""
    if isinstance(value, bytes):
        return {"$bytes": base64.b64encode(value).decode("ascii")}
    if isinstance(value, np.ndarray):
        return {
            "$array": base64.b64encode(value.tobytes()).decode("ascii"),
            "dtype": ELEMENT_OF[value.dtype],
            "shape": list(value.shape),
        }
    if isinstance(value, BlobRef):
        return value.to_json()
    raise TypeError(f"{type(value).__name__} is not a DSR value")


def summary(value: Any) -> dict[str, Any]:
    """What a binary value is, without its bytes, for pages that show the graph (TypeError for
    any other value, so it serves as a JSON encoder's ``default``):
    ``{"$binary": "uint8", "shape": [480, 640, 3], "size": 921600}`` (``shape`` null for bytes)."""
    if isinstance(value, bytes):
        return {"$binary": BYTES, "shape": None, "size": len(value)}
    if isinstance(value, np.ndarray):
        dtype = ELEMENT_OF.get(value.dtype, str(value.dtype))
        return {"$binary": dtype, "shape": list(value.shape), "size": int(value.nbytes)}
    if isinstance(value, BlobRef):
        shape = list(value.shape) if value.shape is not None else None
        return {"$binary": value.dtype, "shape": shape, "size": value.size}
    raise TypeError(f"{type(value).__name__} is not a DSR value")


def equal(a: Any, b: Any) -> bool:
    """Value equality that arrays take part in (same type, shape and elements)."""
    if isinstance(a, np.ndarray) or isinstance(b, np.ndarray):
        return (
            isinstance(a, np.ndarray)
            and isinstance(b, np.ndarray)
            and a.dtype == b.dtype
            and a.shape == b.shape
            and bool(np.array_equal(a, b))
        )
    return a == b


def short_text(value: Any) -> str:
    """A value as a person reads it in a terminal: a binary one (decoded or as JSON) by its type
    and size, anything else as JSON."""
    if isinstance(value, np.ndarray):
        element = ELEMENT_OF.get(value.dtype, str(value.dtype))
        return f"<{element} {'x'.join(map(str, value.shape))}>"
    if isinstance(value, bytes):
        return f"<{len(value)} bytes>"
    if isinstance(value, BlobRef):
        shape = "x".join(map(str, value.shape)) if value.shape is not None else ""
        return f"<{value.dtype} {shape or value.size}, not fetched>"
    if isinstance(value, dict) and ("$bytes" in value or "$array" in value):
        if "$array" in value and isinstance(value.get("shape"), list):
            return f"<{value.get('dtype')} {'x'.join(map(str, value['shape']))}>"
        return f"<{declared_size(value)} bytes>"
    return json.dumps(value)


def dumps(doc: Any, **kwargs: Any) -> str:
    """JSON text of a document that may hold binary values (``json.dumps`` otherwise)."""
    return json.dumps(doc, default=to_json_value, **kwargs)


def compact(doc: Any) -> str:
    """Compact JSON text of a document that may hold binary values, by orjson: what goes on the
    DSR's hot path (each request, delta, journal line and notice), snapshots and recordings;
    0.8 us for a one-op delta against json.dumps's 9 (issue 35). Its text differs from
    json.dumps's only in spelling (no spaces, UTF-8 kept, floats as ``1e-5``) and at what
    safe_json refuses on the way in:
    a NaN is written null (json.dumps wrote NaN, which is no JSON), an integer beyond 64 bits
    is a TypeError."""
    return orjson.dumps(doc, default=_compact_value).decode()


def _compact_value(value: Any) -> Any:
    # json.dumps writes a float's subclasses (numpy's float64) as floats; orjson asks for them
    return float(value) if isinstance(value, float) else to_json_value(value)
