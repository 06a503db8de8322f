"""The MMSE's "close your eyes", seen (pure): the eyes count as closed for the item only once they
stayed closed ``MIN_CLOSED`` seconds of the patient's time, by the frames' capture stamps, so a
blink (a tenth to four tenths of a second) is never an answer."""

from __future__ import annotations

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
