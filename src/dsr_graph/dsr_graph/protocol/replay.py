"""A recording replayed as the viewer's history (formats/mcap_recording.py reads the file; what
its snapshots and deltas mean to a graph is the protocol's)."""

from __future__ import annotations

from pathlib import Path

from dsr_graph.exceptions import RecordingError
from dsr_graph.formats.mcap_recording import dsr_events
from dsr_graph.protocol.blobs import resolve
from dsr_graph.protocol.history import History
from dsr_graph.protocol.volatility import follows


def replay_history(path: str | Path, vocabulary=None) -> History:
    """The recording as the viewer's history: every seq it saw can be shown again."""
    history = History(vocabulary)
    for kind, _time, doc in dsr_events(path):
        if kind == "snapshot":
            history.reset(doc)
        elif history.graph is not None and follows(doc, history.seq):
            # a large binary value (a camera image) is held by its reference: its bytes are on
            # dsr/blobs, which the replay does not read
            history.add(resolve(doc, lambda digest: None, lazy=True))
        # a delta the last snapshot already holds (or one before the first snapshot) is skipped
    if history.graph is None:
        raise RecordingError(f"{path} holds no snapshot of the graph (was the DSR server up?)")
    return history
