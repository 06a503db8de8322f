"""The DSR server's rule for an accepted change: on disk before anyone sees it. Symbolic deltas
are appended to the journal and synced (one fdatasync a batch), then every delta is broadcast in
order; volatile ones (sensor data) are never journalled: a crash loses the latest of them, never
a symbol. If the disk fails nothing is broadcast and ``OSError`` goes to the caller, which must
stop: a restart from what is on disk is consistent, an accepted change not on disk would not be.
Pure: the node gives the store and how to broadcast one delta.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from dsr_graph.formats.state_store import StateStore
from dsr_graph.protocol.blobs import BlobCache, extract
from dsr_graph.protocol.volatility import is_volatile


def journal_then_broadcast(
    store: StateStore,
    deltas: list[dict[str, Any]],
    broadcast: Callable[[dict[str, Any]], None],
) -> bool:
    """True when the journal is long enough for a new snapshot (``store.write_snapshot``)."""
    durable = [delta for delta in deltas if not is_volatile(delta)]
    for delta in durable:
        store.append(delta)
    if durable:
        store.flush()
    for delta in deltas:
        broadcast(delta)
    return store.needs_compaction()


def outgoing(delta: dict[str, Any], cache: BlobCache) -> tuple[dict[str, Any], dict[str, bytes]]:
    """A delta as it goes on the wire (large binary values by digest) and the bytes the wire has
    not carried yet. Bytes an agent sent went to every reader that wants them on the agent's
    own dsr/blobs/<name>: sent again they would cost the server a 2 MB copy a camera frame."""
    doc, blobs = extract(delta, known=cache.digest_of_kept)
    new = {}
    for digest, data in blobs.items():
        if digest not in cache:
            new[digest] = data
        cache.put(digest, data, verified=True)
    return doc, new
