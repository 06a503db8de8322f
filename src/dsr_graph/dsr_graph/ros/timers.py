"""A timer that fires once (rclpy's timers repeat)."""

from __future__ import annotations

from collections.abc import Callable

from rclpy.node import Node


class OneShot:
    """Calls ``callback`` once after ``seconds``, then destroys its timer; ``cancel()`` first
    and it never fires."""

    def __init__(self, node: Node, seconds: float, callback: Callable[[], None]):
        self._node = node
        self._callback = callback
        self._timer = node.create_timer(max(seconds, 0.001), self._fire)

    def _fire(self) -> None:
        self.cancel()
        self._callback()

    def cancel(self) -> None:
        if self._timer is not None:
            self._timer.cancel()
            self._node.destroy_timer(self._timer)
            self._timer = None
