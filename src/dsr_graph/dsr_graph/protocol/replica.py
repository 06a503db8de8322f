"""An agent's copy of the graph: a snapshot plus the deltas after it, applied strictly in sequence.

A delta that arrives before its predecessors is kept aside and the replica reports a gap; the
agent then fetches a snapshot (``load_snapshot``), after which the kept deltas newer than the
snapshot are applied. Duplicates (seq already applied) are ignored. Before the first snapshot
(late join) every delta is kept aside. A volatile delta (sensor data, ``volatility.py``) is
applied only by a replica at exactly the seq it follows, and otherwise skipped, never kept: the
next one carries newer values. Pure logic: the ROS side is in ``agent.py``.
"""

from __future__ import annotations

from typing import Any

from dsr_graph.exceptions import TransactionRejected
from dsr_graph.formats import dsr_json
from dsr_graph.model.claims import ClaimTable
from dsr_graph.model.graph import Graph
from dsr_graph.model.provenance import apply_delta
from dsr_graph.model.vocabulary import Vocabulary
from dsr_graph.protocol.volatility import follows, is_volatile

MAX_PENDING = 100_000  # deltas kept aside while waiting for a snapshot


class Replica:
    def __init__(self, vocabulary: Vocabulary | None = None):
        self.vocabulary = vocabulary
        self.graph = Graph(vocabulary)
        self.graph.trusted_rt = True  # the server's deltas: checked there
        self.claims = ClaimTable()
        self.seq = 0
        self.synced = False  # a snapshot has been loaded
        self.server_seq = 0  # highest seq the server is known to have reached
        # deltas applied so far, volatile ones included: a replica working through a queue of
        # volatile deltas is advancing although its seq is not
        self.applied = 0
        self._pending: dict[int, dict[str, Any]] = {}

    @property
    def needs_resync(self) -> bool:
        """True when a snapshot may be needed: never synced, or the server is ahead of us. Being
        ahead can mean deltas are still on their way (``has_hole`` and ``behind`` tell apart a
        hole from a queue: see DsrAgent's patience)."""
        return not self.synced or self.server_seq > self.seq

    @property
    def has_hole(self) -> bool:
        """A later delta arrived while an earlier one did not: one is missing for sure."""
        return bool(self._pending) and self.synced

    def receive(self, delta: dict[str, Any]) -> list[dict[str, Any]]:
        """Take a delta off the wire; returns the deltas actually applied now, in order."""
        seq = delta["seq"]
        self.server_seq = max(self.server_seq, seq)
        if is_volatile(delta):
            return self._apply_volatile(delta)
        if self.synced and seq <= self.seq:
            return []  # duplicate
        if len(self._pending) >= MAX_PENDING:
            self._pending.clear()  # far behind: a snapshot will cover all of it
        self._pending[seq] = delta
        return self._drain() if self.synced else []

    def _apply_volatile(self, delta: dict[str, Any]) -> list[dict[str, Any]]:
        if not self.synced or self._pending or not follows(delta, self.seq):
            return []  # behind (or ahead): the next one will do
        try:
            apply_delta(self.graph, delta)
        except TransactionRejected:  # diverged (never expected): start over from a snapshot
            self.synced = False
            return []
        self.applied += 1
        return [delta]

    def server_restarted(self, resync: bool) -> None:
        """The server restarted: the deltas kept aside came from the old one and may be lost,
        and its seq starts again from what it made durable. ``resync``: this replica holds
        changes the old one may not have made durable; it loads a snapshot before going on."""
        self._pending.clear()
        self.server_seq = self.seq
        if resync:
            self.synced = False
            self.server_seq = 0

    def observe_server_seq(self, seq: int) -> None:
        """The server says it has reached ``seq`` (heartbeat): a silent gap becomes visible."""
        self.server_seq = max(self.server_seq, seq)

    def load_snapshot(self, doc: dict[str, Any], attrs_hook=None) -> list[dict[str, Any]]:
        """Replace the state with a snapshot, then apply the kept deltas newer than it. Its nodes
        are built as they are first used (``Graph.restore``'s ``lazy``), each element's
        attributes through ``attrs_hook`` then."""
        graph, seq = dsr_json.snapshot_from_json(
            doc, self.vocabulary, trusted=True, lazy=True, attrs_hook=attrs_hook
        )
        graph.trusted_rt = True
        self.graph = graph
        self.claims = ClaimTable.from_json(doc.get("claims", []))
        self.seq = seq
        self.synced = True
        self.server_seq = max(self.server_seq, seq)
        for old in [s for s in self._pending if s <= seq]:
            del self._pending[old]
        return self._drain()

    def _drain(self) -> list[dict[str, Any]]:
        applied = []
        while self.seq + 1 in self._pending:
            delta = self._pending.pop(self.seq + 1)
            try:
                apply_delta(self.graph, delta)
            except TransactionRejected:  # diverged (never expected): start over from a snapshot
                self._pending[delta["seq"]] = delta
                self.synced = False
                break
            self.claims.apply_changes(delta.get("claims", {}))
            self.seq = delta["seq"]
            self.applied += 1
            applied.append(delta)
        return applied
