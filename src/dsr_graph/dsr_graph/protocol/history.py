"""The graph's past, for the viewer's timeline: checkpoints (snapshots) plus the deltas after
them, so the graph at any sequence number seen since the viewer started can be rebuilt (pure)."""

from __future__ import annotations

import bisect
import json
from typing import Any

from dsr_graph.exceptions import SeqUnavailable
from dsr_graph.formats import dsr_json
from dsr_graph.model.binary import dumps
from dsr_graph.model.graph import Graph
from dsr_graph.model.provenance import apply_delta
from dsr_graph.protocol.blobs import extract, resolve
from dsr_graph.protocol.volatility import follows, is_volatile

CHECKPOINT_EVERY = 500  # deltas between stored snapshots: bounds the replay when scrubbing
MAX_DELTAS = 200_000  # the oldest history is forgotten beyond this


class History:
    def __init__(self, vocabulary=None):
        self.vocabulary = vocabulary
        self.graph: Graph | None = None  # the graph now
        self.seq = 0
        self._checkpoints: list[int] = []  # seqs, ascending
        self._snapshots: dict[int, str] = {}  # seq -> snapshot JSON text
        self.deltas: list[dict[str, Any]] = []  # consecutive runs after checkpoints
        self._seqs: list[int] = []  # the deltas' seqs, for bisecting without rebuilding a list

    def reset(self, snapshot: dict[str, Any]) -> None:
        """A snapshot arrived (start, or a resync after a gap): it becomes a checkpoint. The
        document may share its attribute dicts with a live graph (``to_json`` of a replica):
        the history's graph is built from its text, so the two share nothing but the bytes of
        binary values (read-only). A value the replica holds by digest only stays a reference."""
        doc, blobs = extract(snapshot)  # large values beside the text, not as base64 in it
        parsed = resolve(json.loads(dumps(doc)), blobs.get, lazy=True)
        self.graph, self.seq = dsr_json.snapshot_from_json(parsed, self.vocabulary, trusted=True)
        self._checkpoint(dsr_json.to_json(self.graph, "snapshot", seq=self.seq))

    def add(self, delta: dict[str, Any]) -> None:
        """The next delta. A volatile one (sensor data) changes the graph now but takes no place
        in the timeline: a past seq shows its sensor values as of the checkpoint before it."""
        if self.graph is None or not follows(delta, self.seq):
            raise SeqUnavailable(f"delta {delta.get('seq')} does not follow seq {self.seq}")
        apply_delta(self.graph, delta)
        if is_volatile(delta):
            return
        self.seq = delta["seq"]
        self.deltas.append(delta)
        self._seqs.append(delta["seq"])
        if len(self.deltas) > MAX_DELTAS:
            self._forget()
        if self.seq - self._checkpoints[-1] >= CHECKPOINT_EVERY:
            self._checkpoint(dsr_json.to_json(self.graph, "snapshot", seq=self.seq))

    @property
    def first_seq(self) -> int:
        return self._checkpoints[0] if self._checkpoints else 0

    def graph_at(self, seq: int) -> Graph:
        if self.graph is None or not self.first_seq <= seq <= self.seq:
            raise SeqUnavailable(f"seq {seq} is not in the history ({self.first_seq}..{self.seq})")
        if seq == self.seq:
            return self.graph
        base = self._checkpoints[bisect.bisect_right(self._checkpoints, seq) - 1]
        past = resolve(json.loads(self._snapshots[base]), lambda digest: None, lazy=True)
        graph, _ = dsr_json.snapshot_from_json(past, self.vocabulary, trusted=True)
        start = bisect.bisect_right(self._seqs, base)
        for delta in self.deltas[start:]:
            if delta["seq"] > seq:
                break
            if delta["seq"] != base + 1:
                raise SeqUnavailable(f"seq {seq} falls in a gap of the history")
            apply_delta(graph, delta)
            base = delta["seq"]
        if base != seq:  # the deltas stop short of seq: it lies in a gap
            raise SeqUnavailable(f"seq {seq} falls in a gap of the history")
        return graph

    def since(self, seq: int, limit: int = 1000) -> list[dict[str, Any]]:
        start = bisect.bisect_right(self._seqs, seq)
        return self.deltas[start : start + limit]

    def _checkpoint(self, snapshot: dict[str, Any]) -> None:
        """Kept as text, a large binary value (a camera image) by its reference only: the past
        shows what the image was, not its pixels, and a long run's history stays small."""
        if not self._checkpoints or self.seq > self._checkpoints[-1]:
            self._checkpoints.append(self.seq)
        self._snapshots[self.seq] = dumps(extract(snapshot)[0])

    def _forget(self) -> None:
        cut = self.deltas[len(self.deltas) // 2]["seq"]
        keep = [s for s in self._checkpoints if s >= cut] or [self._checkpoints[-1]]
        for s in self._checkpoints:
            if s not in keep:
                del self._snapshots[s]
        self._checkpoints = keep
        self.deltas = [d for d in self.deltas if d["seq"] > keep[0]]
        self._seqs = [d["seq"] for d in self.deltas]
