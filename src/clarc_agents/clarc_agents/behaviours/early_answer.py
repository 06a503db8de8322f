"""An answer given just before its window opened (the patient did not wait for the robot to
finish asking): kept a moment, and used if a window for the same item opens in time. Speech
keeps words, Panel a tap, a drawing or the shapes touched (pure).

An answer to the last sentence the robot began (for the agents that see them: Speech, Panel) is
kept until the window opens, however late: PELEA may hold the window's opening after asking (an
agent it needs restarting: a chaos run killed Panel just as the options were said again, the
patient answered at once and the window opened 4 s later, its answer dropped and the item left
unanswered). Once the robot begins another sentence, the answer was to an earlier one and only
the moment counts.

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
        # whether the robot began a sentence after what is kept; None for an agent that does
        # not see the robot's sentences (Person's eyes): the moment alone counts there
        self._asked_since: bool | None = None

    def keep(self, answer: Any, item: str) -> None:
        self._kept = (answer, item, self.now())
        if self._asked_since is not None:
            self._asked_since = False

    def asked(self) -> None:
        """The robot began a sentence: what is kept now answers an earlier one."""
        self._asked_since = True

    def peek(self, item: str) -> Any | None:
        """What is kept for ``item`` (recent or not), left kept."""
        return self._kept[0] if self._kept is not None and self._kept[1] == item else None

    def take(self, item: str) -> Any | None:
        """The answer kept for ``item``, if it answers the robot's last sentence or is recent;
        what was kept is dropped either way."""
        kept, self._kept = self._kept, None
        if kept is None or kept[1] != item:
            return None
        if self._asked_since is False:
            return kept[0]
        since = kept[2]
        went, came = self.server_gap()
        if since <= came and went <= since + PATIENCE:  # still fresh when the link went down
            since = came
        return kept[0] if self.now() - since <= PATIENCE else None
