"""A short-lived ROS session for command-line tools and tests: its own context and node, and
bounded waits (never an unbounded spin)."""

from __future__ import annotations

import os
import time
from collections.abc import Callable
from typing import Any

import rclpy
from rclpy.context import Context
from rclpy.executors import SingleThreadedExecutor

from dsr_graph.exceptions import TimedOutError
from dsr_graph.ros import dds_deadlock, dds_teardown
from dsr_graph.ros.exit_timer import TEARDOWN_LIMIT, exit_if_stuck, exit_now


class RosSession:
    def __init__(
        self,
        name: str | None = None,
        domain_id: int | None = None,
        ros_args: list[str] | None = None,
        executor: Callable = SingleThreadedExecutor,
    ):
        """``ros_args`` (``--ros-args -r __ns:=/robot ...``) apply to this session's node:
        namespaces, remaps, parameters, as for any ROS node. ``executor``: what spins it (a
        benchmark's agents take the DsrNode agents' EventsExecutor)."""
        self.context = Context()
        rclpy.init(args=["session", *(ros_args or [])], context=self.context, domain_id=domain_id)
        # the event thread of the participant made with the node: close() checks it is not stuck
        with dds_deadlock.new_event_threads() as self._event_threads:
            self.node = rclpy.create_node(name or f"dsr_cli_{os.getpid()}", context=self.context)
        self.executor = executor(context=self.context)
        self.executor.add_node(self.node)
        # A one-shot tool whose work is done and told sets the code it exits with should its
        # DDS goodbye hang (exit_timer.py: Fast DDS can spin there forever, and the tool's
        # caller, a launch, would wait on it). None (tests, tools still to print): not bounded.
        self.stuck_exit: int | None = None

    def __enter__(self) -> RosSession:
        return self

    def __exit__(self, *exc: Any) -> None:
        self.close()

    def close(self) -> None:
        # other nodes made in this session's context (a second agent, a reader) go too: while
        # one lives, the context's participant still announces its name, and the next node of
        # that name in the domain would be refused as a duplicate (identity.py)
        others = [n for n in self.executor.get_nodes() if n is not self.node]
        self.executor.shutdown(timeout_sec=1.0)
        # a participant Fast DDS deadlocked (dds_deadlock) is left as it is: destroying any of
        # its nodes would wait for ever
        jammed = dds_deadlock.stuck(self._event_threads)
        if jammed:
            dds_deadlock.abandon([*others, self.node, self.executor, self.context], jammed)
            if self.stuck_exit is not None:  # a tool whose work is done and told ends here
                exit_now(self.stuck_exit)
            return
        for node in others:
            node.destroy_node()
        if self.stuck_exit is None:
            dds_teardown.destroy_node(self.node, ())
        else:
            with exit_if_stuck(TEARDOWN_LIMIT, self.stuck_exit):
                dds_teardown.destroy_node(self.node, ())
        rclpy.try_shutdown(context=self.context)

    def spin_for(self, seconds: float) -> None:
        deadline = time.monotonic() + seconds
        while time.monotonic() < deadline:
            self.executor.spin_once(timeout_sec=min(0.05, max(0.0, deadline - time.monotonic())))

    def follow(self, done: Callable[[], bool], duration: float = 0.0) -> None:
        """Spin until ``done()``, ``duration`` seconds (0: no limit) or Ctrl-C: a tool that
        follows a stream (``dsr watch``, ``dsr echo``)."""
        deadline = time.monotonic() + duration if duration else None
        try:
            while not done():
                if deadline is not None and time.monotonic() >= deadline:
                    return
                self.executor.spin_once(timeout_sec=0.1)
        except KeyboardInterrupt:
            pass

    def spin_until(self, done: Callable[[], bool], timeout_sec: float, what: str) -> None:
        """Spin until ``done()``; ``TimedOutError`` naming ``what`` after ``timeout_sec``."""
        deadline = time.monotonic() + timeout_sec
        while not done():
            if time.monotonic() >= deadline:
                raise TimedOutError(f"timed out after {timeout_sec} s waiting for {what}")
            self.executor.spin_once(timeout_sec=0.05)

    def call(self, client, request, timeout_sec: float, what: str, attempt_sec: float = 1.0):
        """Call a service, bounded. A request sent while the server is restarting can be lost
        (DDS still lists the old server), so an unanswered request is withdrawn and sent again
        every ``attempt_sec`` until ``timeout_sec``."""
        deadline = time.monotonic() + timeout_sec
        while True:
            remaining = deadline - time.monotonic()
            if remaining <= 0 or not client.wait_for_service(timeout_sec=remaining):
                raise TimedOutError(
                    f"no answer from {client.srv_name} within {timeout_sec} s waiting for {what} "
                    "(is dsr_server running with the same ROS_DOMAIN_ID?)"
                )
            future = client.call_async(request)
            try:
                self.spin_until(
                    future.done, min(attempt_sec, max(0.0, deadline - time.monotonic())), what
                )
                return future.result()
            except TimedOutError:
                client.remove_pending_request(future)
