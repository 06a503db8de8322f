"""An answer given just before its window opened (the patient did not wait for the robot to
finish asking): kept a moment, and used if a window for the same item opens in time. Speech
keeps words, Panel a tap, a drawing or the shapes touched (pure).

On a network cut the patient may answer a question the agent showed while the window's opening
is held on the far side of the link: if the server went out of the agent's reach while the
answer was still fresh, the moment counts from when it came back."""

from __future__ import annotations

import time
from collections.abc import Callable
from typing import Any

PATIENCE = 2.0  # seconds an early answer is kept for the window about to open
NO_GAP = (float("-inf"), float("-inf"))


class EarlyAnswer:
    def __init__(
        self,
        now: Callable[[], float] = time.monotonic,
        server_gap: Callable[[], tuple[float, float]] = lambda: NO_GAP,
    ):
        self.now = now
        self.server_gap = server_gap  # the server's last silence: (last heard before, heard again)
        self._kept: tuple[Any, str, float] | None = None  # (answer, item shown, when)

    def keep(self, answer: Any, item: str) -> None:
        self._kept = (answer, item, self.now())

    def peek(self, item: str) -> Any | None:
        """What is kept for ``item`` (recent or not), left kept."""
        return self._kept[0] if self._kept is not None and self._kept[1] == item else None

    def take(self, item: str) -> Any | None:
        """The answer kept for ``item``, if it is recent; what was kept is dropped either way."""
        kept, self._kept = self._kept, None
        if kept is None or kept[1] != item:
            return None
        since = kept[2]
        went, came = self.server_gap()
        if since <= came and went <= since + PATIENCE:  # still fresh when the link went down
            since = came
        return kept[0] if self.now() - since <= PATIENCE else None
