"""The DSR server's rule for an accepted change: visible first, durable before acknowledged.
Symbolic deltas go to the journal's group commit (formats/group_commit.py), then every delta is
broadcast in order, each carrying the seq durable at that moment; the commit thread makes them
durable and says so, and only then does a writer hear its verdict (protocol/agent_core.py).
Volatile ones (sensor data) are never journalled: a crash loses the latest of them, never an
acknowledged symbol. Pure: the node gives the commit and how to broadcast one delta.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from dsr_graph.formats.group_commit import GroupCommit
from dsr_graph.protocol.blobs import BlobCache, extract
from dsr_graph.protocol.volatility import is_volatile


def broadcast_then_commit(
    commit: GroupCommit,
    deltas: list[dict[str, Any]],
    broadcast: Callable[[dict[str, Any]], None],
) -> bool:
    """True when the journal is long enough for a new snapshot (``commit.compact``)."""
    for delta in deltas:  # the commit thread may start on them while they are broadcast
        if not is_volatile(delta):
            commit.append(delta)
    for delta in deltas:
        broadcast(delta)
    return commit.store.needs_compaction()


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
