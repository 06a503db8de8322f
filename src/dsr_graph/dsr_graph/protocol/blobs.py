"""Binary values beside the JSON (pure): a request or a delta carries each large binary value
(a camera image) as a reference, ``{"$blob": "sha256:<hex>", "dtype", "shape", "size"}``, and
its bytes travel apart, as CDR on a blob topic (``dsr_msgs/msg/Blob``: the digest and the
bytes), never as JSON text. The digest in the (signed) JSON is what binds the bytes: bytes
that do not hash to it are nobody's.

    doc, blobs = extract(delta)               # the JSON to send, {digest: bytes} to send beside
    cache.put(digest, data)                   # as blobs arrive (False: not what they claim)
    doc = resolve(doc, cache.get)             # the server: MissingBlob if one has not come
    doc = resolve(doc, cache.get, lazy=True)  # a replica: a BlobRef where one has not come

Values under ``INLINE_MAX`` bytes stay inline (base64, ``binary.py``): a blob's own message
costs more than they do.

Sensor data (a volatile attribute's value, a camera frame) goes one hop: its reference names
the writer, ``{"at": "<node name>", "$blob": ...}``, its bytes go on the writer's
``dsr/sensor_blobs/<node name>``, which the server never reads, straight to the replicas that
want them; the server sequences and signs the change by its digest and keeps a ``BlobRef``.

    doc, blobs = extract(request, sensor_at=lambda attr: name if attr in volatile else None)
    sensor_refs_in_text(dumps(doc))           # the digests that go on dsr/sensor_blobs/<name>
    resolve(request, cache.get, lazy=volatile)   # the server: a BlobRef for sensor data only
"""

from __future__ import annotations

import array
import hashlib
import math
import re
from collections import OrderedDict
from collections.abc import Callable, Container
from typing import Any

import numpy as np

from dsr_graph.exceptions import MissingBlob, ValueTypeError
from dsr_graph.model.binary import ARRAYS, BYTES, ELEMENT_OF, ITEMSIZE_OF, BlobRef, _shape
from dsr_graph.protocol.topic_names import GET_BLOB

REF = "$blob"
INLINE_MAX = 16 * 1024  # bytes: a binary value this big or bigger travels as a blob
DIGEST = re.compile(r"sha256:[0-9a-f]{64}")
DTYPES = {element: dtype for element, dtype in ARRAYS.values()}
Blob = bytes | array.array  # a blob's bytes: a received message's array is kept as it came
_REF_IN_TEXT = re.compile(r'"\$blob"\s*:\s*"(sha256:[0-9a-f]{64})"')
# a sensor blob's reference as BlobRef.to_json writes it: "at" first
_SENSOR_REF_IN_TEXT = re.compile(
    r'"at"\s*:\s*"[^"\\]*"\s*,\s*"\$blob"\s*:\s*"(sha256:[0-9a-f]{64})"'
)
NODE_NAME = re.compile(r"[A-Za-z_][A-Za-z0-9_]{0,254}")  # a ROS node's name: where bytes are held


def digest_of(data: Blob | memoryview) -> str:
    return "sha256:" + hashlib.sha256(data).hexdigest()


def _payload(value: Any) -> tuple[Blob, str, tuple[int, ...] | None] | None:
    """(bytes, dtype, shape) of a binary value worth a blob; None: it stays inline."""
    if isinstance(value, (bytes, bytearray, memoryview)):
        return (bytes(value), BYTES, None) if len(value) >= INLINE_MAX else None
    if isinstance(value, np.ndarray) and value.nbytes >= INLINE_MAX:
        element = ELEMENT_OF.get(value.dtype.newbyteorder("<")) or ELEMENT_OF.get(value.dtype)
        if element is None:
            return None  # not a DSR array type: left for the coercer to refuse by name
        base = value.base
        while isinstance(base, (np.ndarray, memoryview)):  # through the views to the memory
            base = base.base if isinstance(base, np.ndarray) else base.obj
        if isinstance(base, (bytes, array.array)) and value.flags.c_contiguous:
            if memoryview(base).nbytes == value.nbytes and value.dtype == DTYPES[element]:
                return base, element, tuple(value.shape)  # made from a blob: its bytes
        little = np.ascontiguousarray(value, dtype=DTYPES[element])
        return little.tobytes(), element, tuple(value.shape)
    return None


ELEMENTS = ("ops", "nodes", "edges")  # where a request, a delta or a snapshot holds "attrs"


def extract(
    doc: dict[str, Any],
    known: Callable[[Blob], str | None] = lambda data: None,
    sensor_at: Callable[[str], str | None] = lambda attribute: None,
) -> tuple[dict[str, Any], dict[str, Blob]]:
    """``doc`` (a request, a delta or a snapshot) with each large binary value of its ops',
    nodes' or edges' ``attrs`` replaced by its reference, and the bytes by digest. ``doc``
    itself is not changed. ``known``: the digest of bytes already hashed (a value made from a
    blob), else None. ``sensor_at``: for an attribute that holds sensor data, the name of the
    node whose sensor blob topic carries its bytes (the reference says so), else None."""
    blobs: dict[str, Blob] = {}

    def referenced(attrs: dict[str, Any]) -> dict[str, Any] | None:
        new_attrs = None
        for name, value in attrs.items():
            payload = _payload(value)
            if payload is None:
                continue
            data, dtype, shape = payload
            digest = known(data) or digest_of(data)
            blobs[digest] = data
            new_attrs = dict(attrs) if new_attrs is None else new_attrs
            ref = BlobRef(digest, dtype, shape, memoryview(data).nbytes, sensor_at(name))
            new_attrs[name] = ref.to_json()
        return new_attrs

    return _rewrite(doc, referenced), blobs


def _rewrite(doc: dict[str, Any], change: Callable[[dict[str, Any]], dict[str, Any] | None]):
    """``doc`` with ``change`` applied to each element's ``attrs`` (None: left as it is), the
    lists and elements copied only where something changed."""
    out = None
    for key in ELEMENTS:
        elements = doc.get(key)
        if not isinstance(elements, list):
            continue
        new_list = None
        for i, element in enumerate(elements):
            attrs = element.get("attrs") if isinstance(element, dict) else None
            new_attrs = change(attrs) if isinstance(attrs, dict) else None
            if new_attrs is not None:
                new_list = list(elements) if new_list is None else new_list
                new_list[i] = {**element, "attrs": new_attrs}
        if new_list is not None:
            out = dict(doc) if out is None else out
            out[key] = new_list
    return doc if out is None else out


def holder_of(at: str | None) -> str:
    """The dsr/get_blob service that holds a value's bytes: the server's, or for sensor data
    (a ``BlobRef`` with ``at``) its writer's, ``dsr/get_blob/<node name>``."""
    return GET_BLOB if not at else f"{GET_BLOB}/{at}"


def refs_in_text(text: str) -> set[str]:
    """The digests a request's or a delta's JSON text references (before it is parsed)."""
    return set(_REF_IN_TEXT.findall(text)) if REF in text else set()


def sensor_refs_in_text(text: str) -> set[str]:
    """The digests of the sensor blobs a request's JSON text references (an "at" before the
    "$blob", as ``BlobRef.to_json`` writes it): their bytes go on the writer's sensor topic."""
    return set(_SENSOR_REF_IN_TEXT.findall(text)) if REF in text else set()


def held_refs_in_text(text: str) -> set[str]:
    """The digests a request's JSON text references whose bytes come to the server: all but the
    sensor blobs' (each an "at" before its "$blob", as ``BlobRef.to_json`` writes it)."""
    return refs_in_text(text) - sensor_refs_in_text(text)


def _ref(value: Any) -> BlobRef:
    """A reference as JSON gives it, checked: every field named when wrong."""
    digest, dtype, size = value.get(REF), value.get("dtype"), value.get("size")
    if not isinstance(digest, str) or not DIGEST.fullmatch(digest):
        raise ValueTypeError(f'"{REF}" must be "sha256:" and 64 hex digits, got {digest!r}')
    if dtype != BYTES and dtype not in ITEMSIZE_OF:
        raise ValueTypeError(f"a blob's dtype is bytes or one of {sorted(ITEMSIZE_OF)}: {dtype!r}")
    if not isinstance(size, int) or isinstance(size, bool) or size < 0:
        raise ValueTypeError(f"a blob's size is a number of bytes, got {size!r}")
    shape = None
    if dtype != BYTES:
        shape = _shape(value.get("shape"))
        if math.prod(shape) * ITEMSIZE_OF[dtype] != size:
            raise ValueTypeError(f"a blob of shape {list(shape)} of {dtype} is not {size} bytes")
    at = value.get("at")
    if at is not None and (not isinstance(at, str) or not NODE_NAME.fullmatch(at)):
        raise ValueTypeError(f'a blob\'s "at" is the name of the node holding it, got {at!r}')
    extra = set(value) - {REF, "dtype", "size", "shape", "at"}
    if extra:
        raise ValueTypeError(f"unknown key(s) in a blob reference: {', '.join(sorted(extra))}")
    return BlobRef(digest, dtype, shape, size, at)


def _value(ref: BlobRef, data: Blob) -> Any:
    size = memoryview(data).nbytes
    if size != ref.size:
        raise ValueTypeError(f"the binary value {ref.digest} is {size} bytes, not {ref.size}")
    return binary_value(ref.dtype, ref.shape, data)


def binary_value(dtype: str, shape: tuple[int, ...] | None, data: Blob) -> Any:
    """A binary value from its bytes: ``bytes``, or a read-only array of that element type and
    shape over the bytes themselves (never copied, never changed)."""
    if dtype == BYTES:
        return bytes(data)
    value = np.frombuffer(data, dtype=DTYPES[dtype]).reshape(shape)
    value.flags.writeable = False
    return value


def resolve(
    doc: dict[str, Any],
    lookup: Callable[[str], Blob | None],
    lazy: bool | Container[str] = False,
    held_at: str | None = None,
) -> dict[str, Any]:
    """``doc`` with each reference in its ops', nodes' or edges' ``attrs`` replaced by its
    value (bytes or a read-only array). A reference whose bytes ``lookup`` does not have:
    ``MissingBlob``, or with ``lazy`` a ``BlobRef`` (a replica fetches it when it is read);
    ``lazy`` may be the attributes for which a ``BlobRef`` is taken (the server: sensor data),
    and ``held_at`` the node such a ``BlobRef`` names as holding the bytes (the server: the
    request's sender, whatever the request said). A malformed reference: ``ValueTypeError``."""
    return _rewrite(doc, _resolver(lookup, lazy, held_at))


def attrs_resolver(
    lookup: Callable[[str], Blob | None],
) -> Callable[[dict[str, Any]], dict[str, Any]]:
    """``resolve(..., lazy=True)`` for one element's ``attrs`` (the same dict when it holds no
    reference): a replica's snapshot resolves each element's as it builds it."""
    resolved = _resolver(lookup, lazy=True)
    return lambda attrs: resolved(attrs) or attrs


def _resolver(
    lookup: Callable[[str], Blob | None], lazy: bool | Container[str], held_at: str | None = None
):
    def resolved(attrs: dict[str, Any]) -> dict[str, Any] | None:
        for value in attrs.values():  # (a loop: this runs for every element of a snapshot)
            if type(value) is dict and REF in value:
                break
        else:
            return None
        new_attrs = dict(attrs)
        for name, value in attrs.items():
            if not (isinstance(value, dict) and REF in value):
                continue
            ref = _ref(value)
            data = lookup(ref.digest)
            if data is None:
                if not (lazy is True or (lazy is not False and name in lazy)):
                    raise MissingBlob(ref.digest)
                if held_at is not None:
                    ref.at = held_at
                new_attrs[name] = ref
            else:
                new_attrs[name] = _value(ref, data)
        return new_attrs

    return resolved


class BlobCache:
    """Blobs by digest, the newest kept up to ``max_bytes`` in all (the oldest go first)."""

    def __init__(self, max_bytes: int = 256 * 1024 * 1024):
        self.max_bytes = max_bytes
        self.bytes = 0
        self._blobs: OrderedDict[str, Blob] = OrderedDict()
        self._digests: dict[int, str] = {}  # id of the bytes kept -> their digest

    def put(self, digest: str, data: Blob, verified: bool = False) -> bool:
        """Keep ``data`` under ``digest`` if it hashes to it (``verified``: hashed already);
        False, and nothing kept, if it does not."""
        if not verified and (not DIGEST.fullmatch(digest) or digest_of(data) != digest):
            return False
        if digest in self._blobs:
            self._blobs.move_to_end(digest)
            return True
        self._blobs[digest] = data
        self._digests[id(data)] = digest
        self.bytes += memoryview(data).nbytes
        while self.bytes > self.max_bytes and len(self._blobs) > 1:
            _, old = self._blobs.popitem(last=False)
            del self._digests[id(old)]
            self.bytes -= memoryview(old).nbytes
        return True

    def get(self, digest: str) -> Blob | None:
        return self._blobs.get(digest)

    def digest_of_kept(self, data: Blob) -> str | None:
        """The digest of ``data`` if it is the very bytes kept under it (no hashing again)."""
        digest = self._digests.get(id(data))
        return digest if digest is not None and self._blobs.get(digest) is data else None

    def __contains__(self, digest: str) -> bool:
        return digest in self._blobs

    def __len__(self) -> int:
        return len(self._blobs)
