"""A snapshot as the DSR server sends it on dsr/get_snapshot: large binary values by digest (their
bytes go on dsr/blobs), as one document or column by column (a replica parses only the elements
it uses: formats/dsr_json.to_columns). Pure."""

from __future__ import annotations

from collections.abc import Callable

from dsr_graph.formats import dsr_json
from dsr_graph.model.binary import compact
from dsr_graph.protocol.blobs import extract
from dsr_graph.protocol.server_core import ServerCore

LAYOUTS = ("", dsr_json.COLUMNS)


def snapshot_text(
    core: ServerCore, layout: str, known: Callable[[bytes], str | None]
) -> tuple[str, dict[str, bytes]]:
    """(the snapshot's JSON, the bytes of the binary values it names). ``known``: the digest of
    bytes already kept (BlobCache.digest_of_kept), so that none is hashed twice."""
    if layout not in LAYOUTS:
        raise ValueError(f"unknown layout {layout!r} ('' or {dsr_json.COLUMNS!r})")
    snapshot, blobs = extract(core.snapshot(), known=known)
    if layout == dsr_json.COLUMNS:
        snapshot = dsr_json.to_columns(snapshot, compact)
    return compact(snapshot), blobs
