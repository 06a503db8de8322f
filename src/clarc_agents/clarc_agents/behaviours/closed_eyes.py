"""The MMSE's "close your eyes", seen (pure): the eyes count as closed for the item only once they
stayed closed ``MIN_CLOSED`` seconds of the patient's time, by the frames' capture stamps, so a
blink (a tenth to four tenths of a second) is never an answer.

The patient reads the instruction on the screen and may close the eyes before the robot has
finished asking, or before the window's opening reaches Person on a busy machine: a closing seen
while the ``eyes`` item is on the screen and no answer is awaited is kept a moment
(``early_answer.PATIENCE``) and answers that item's window when it opens, as Panel keeps a tap."""

from __future__ import annotations

import time
from collections.abc import Callable

from clarc_agents.behaviours.early_answer import EarlyAnswer
from clarc_agents.questionnaire.item_options import awaited_item, item_in, item_on_screen
from dsr_graph.model.graph import Graph

MIN_CLOSED = 1.0  # seconds of the patient's time
STAMP_ROUNDING = 1e-6  # s: a stamp's float rounding, so exactly a second counts


class ClosedEyes:
    def __init__(self, scale: float = 1.0):
        self.scale = scale  # wall seconds per second of the patient's time
        self.since: float | None = None  # the stamp of the first frame of this closing

    def see(self, closed: bool, stamp: float) -> bool:
        """A frame: whether the eyes have now been closed long enough (an open frame, or a
        frame without the patient, starts the count again)."""
        if not closed:
            self.since = None
            return False
        if self.since is None:
            self.since = stamp
        return (stamp - self.since) / self.scale >= MIN_CLOSED - STAMP_ROUNDING


class EyesAnswer:
    """The points an ``eyes`` item's window gets from the camera, and when."""

    def __init__(self, scale: float = 1.0, now: Callable[[], float] = time.monotonic):
        self.closed = ClosedEyes(scale)
        self._early = EarlyAnswer(now)  # a closing seen just before its window opened

    def see(self, graph: Graph, closed: bool, stamp: float) -> int | None:
        """A frame of the patient: the points to answer the awaited item with, if it is an
        ``eyes`` item and the eyes have been closed long enough; a closing with no answer
        awaited is kept for the window of the ``eyes`` item on the screen."""
        if not self.closed.see(closed, stamp):
            return None
        item = awaited_item(graph)
        if item is not None:
            return item.max if item.kind == "eyes" else None
        if graph.edge("person", "answer", "waiting") is None:
            shown = item_on_screen(graph)
            on_screen = item_in(graph, shown) if shown else None
            if on_screen is not None and on_screen.kind == "eyes":
                self._early.keep(on_screen.max, shown)
        return None

    def on_graph(self, graph: Graph) -> int | None:
        """The graph changed: if a window opened for the ``eyes`` item whose closing was kept,
        the points it gets."""
        waiting = graph.edge("person", "answer", "waiting")
        if waiting is None:
            return None
        points = self._early.take(str(waiting.attrs.get("item", "")))
        item = awaited_item(graph) if points is not None else None
        return points if item is not None and item.kind == "eyes" else None
