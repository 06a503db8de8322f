"""An answer given just before its window opened (the patient did not wait for the robot to
finish asking): kept a moment, and used if a window for the same item opens in time. Speech
keeps words, Panel keeps a tap (pure)."""

from __future__ import annotations

import time
from collections.abc import Callable
from typing import Any

PATIENCE = 2.0  # seconds an early answer is kept for the window about to open


class EarlyAnswer:
    def __init__(self, now: Callable[[], float] = time.monotonic):
        self.now = now
        self._kept: tuple[Any, str, float] | None = None  # (answer, item shown, when)

    def keep(self, answer: Any, item: str) -> None:
        self._kept = (answer, item, self.now())

    def take(self, item: str) -> Any | None:
        """The answer kept for ``item``, if it is recent; what was kept is dropped either way."""
        kept, self._kept = self._kept, None
        if kept is not None and kept[1] == item and self.now() - kept[2] <= PATIENCE:
            return kept[0]
        return None
