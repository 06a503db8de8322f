"""The undo log of the transaction in progress: every mutation of the graph records how to undo
itself, and a failing transaction runs the steps backwards, so it leaves the graph exactly as it
found it. Pure."""

from __future__ import annotations

from collections.abc import Callable


class UndoLog:
    def __init__(self) -> None:
        self._steps: list[Callable[[], None]] | None = None

    def begin(self) -> None:
        if self._steps is not None:
            raise RuntimeError("atomic() blocks do not nest")
        self._steps = []

    def record(self, step: Callable[[], None]) -> None:
        """Remember how to undo a change (nothing is recorded outside a transaction)."""
        if self._steps is not None:
            self._steps.append(step)

    def rollback(self) -> None:
        """Undo every recorded change, newest first. Undo steps record nothing themselves."""
        steps, self._steps = self._steps or [], None
        for step in reversed(steps):
            step()

    def end(self) -> None:
        self._steps = None
