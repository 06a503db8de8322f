"""Serving a web app next to a ROS node: rclpy spins in a background thread, aiohttp serves in
the main thread's asyncio loop (``dsr_graph.web.events.Broadcaster`` fans events out to the open
pages). ROS callbacks hand data to the web side with ``Bridge.to_web`` (never share objects
between the threads without it)."""

from __future__ import annotations

import asyncio
import threading
from collections.abc import Callable
from typing import Any

from aiohttp import web
from rclpy.executors import Executor, ExternalShutdownException

from dsr_graph.ros.dsr_node import DsrNode

STOP_CHECK = 0.1  # seconds: how soon the ROS thread sees that the web side is done
THREAD_END = 10.0  # seconds the web side waits for the ROS thread to end its callback


class Bridge:
    def __init__(self, node, executor: Executor | None = None):
        self.node = node
        # the executor every node spins, which stops safely on a signal (DsrNode.EXECUTOR)
        self.executor = executor or DsrNode.EXECUTOR(context=node.context)
        self.executor.add_node(node)
        self.loop: asyncio.AbstractEventLoop | None = None
        self._stop: asyncio.Event | None = None
        self.failed = False
        self._stopping = False  # set by the web side when it is done: the ROS thread ends
        self._thread = threading.Thread(target=self._spin, name="rclpy", daemon=True)

    def _spin(self) -> None:
        try:
            while not self._stopping:
                self.executor.spin_once(timeout_sec=STOP_CHECK)
        except ExternalShutdownException:  # Ctrl-C / SIGTERM: rclpy's handler shut ROS down
            pass
        except Exception as e:
            # A signal that shut ROS down between two turns makes the next one fail on the dead
            # context ("failed to create timer": spin_once's timeout timer), not raise
            # ExternalShutdownException: that is a stop too. Anything else is a failing
            # callback: say so and stop the whole process.
            if self.node.context.ok():
                self.failed = True
                self.node.get_logger().fatal(f"ROS thread stopped: {e!r}")
        # Either way the web side has nothing left to serve: end the process.
        if self.loop is not None and not self.loop.is_closed():
            self.loop.call_soon_threadsafe(self._stop.set)

    def to_web(self, fn: Callable[..., None], *args: Any) -> None:
        """Run ``fn(*args)`` in the web loop (call from ROS callbacks)."""
        if self.loop is not None and not self.loop.is_closed():
            self.loop.call_soon_threadsafe(fn, *args)

    def serve(
        self,
        app: web.Application,
        host: str,
        port: int,
        on_ready: Callable[[str], None] | None = None,
    ) -> bool:
        """Spin ROS in the background and serve ``app`` until interrupted (True) or until the ROS
        thread fails (False)."""

        async def main() -> None:
            self.loop = asyncio.get_running_loop()
            self._stop = asyncio.Event()
            self._thread.start()
            runner = web.AppRunner(app, access_log=None)
            await runner.setup()
            site = web.TCPSite(runner, host, port)
            await site.start()
            if on_ready:  # the port bound, which the system chose when asked for 0
                bound = runner.addresses[0][1] if runner.addresses else port
                on_ready(f"http://{host}:{bound}/")
            try:
                await self._stop.wait()
            finally:
                await runner.cleanup()

        try:
            asyncio.run(main())
        except KeyboardInterrupt:
            pass
        finally:
            # The ROS thread leaves its callback before the executor and the node go: rclpy's
            # Executor.shutdown does not wait for it (its wait is skipped once shut down), and a
            # thread still in a callback on a node being destroyed, or in a wait set on the
            # executor's destroyed guard condition, aborts the process (SIGABRT, "terminate called
            # without an active exception": dsr_viewer under ros2 launch's SIGINT).
            self._stopping = True
            if self._thread.is_alive():
                self._thread.join(THREAD_END)
            self.executor.shutdown(timeout_sec=0)
        return not self.failed
