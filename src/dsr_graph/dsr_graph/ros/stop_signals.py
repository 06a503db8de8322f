"""SIGINT and SIGTERM, as every node of the suite takes them: the first one raises
KeyboardInterrupt in the main thread (a wait cut short, as Ctrl-C does), but not while ROS
callbacks run (``interrupting`` off in ``DsrNode.spin_once``: a callback is never torn in half,
a transaction never half applied; the spin loop polls ``arrived()`` instead), and whether one
has arrived is known from the instant it did (``arrived()``).

rclpy's own handlers are off (``run_node`` inits with ``SignalHandlerOptions.NO``): they shut
the context down from a signal thread of rclpy's while the main thread, stopping on the same
signal, frees what that thread walks (the wait-set executors' guard conditions: a SIGSEGV at a
launch's end, core in rcl_trigger_guard_condition; and once the events executor's, inside its
spin_once). With them off, only the main thread stops ROS, after it has left its spin.

Python's own C handler writes the signal's number to the wakeup fd before anything the signal
causes, so ``arrived()`` is true even where the KeyboardInterrupt came out disguised (seen: one
raised inside a message's conversion came out of rclpy's ``take_message`` as pybind's
"RuntimeError: Unable to convert call argument '0'").
"""

from __future__ import annotations

import signal
import socket
import threading

STOPS = (signal.SIGINT, signal.SIGTERM)


def _once_then_default(signum, _frame) -> None:
    # the process is stopping already; a second one ends it as the signal's default action does
    signal.signal(signum, signal.SIG_DFL)


def stopping_anyway() -> None:
    """From here the process only ends: the next SIGINT or SIGTERM (launch's SIGTERM 5 s after
    its SIGINT, when a busy machine makes the interpreter's teardown slow) asks for what is
    already happening, and must not turn the node's exit code into a death by that signal (seen
    under load: five nodes of a ros2 launch "died" with -15 after they had stopped); a second
    one ends the process as the signal's default action does."""
    if threading.current_thread() is threading.main_thread():
        for signum in STOPS:
            signal.signal(signum, _once_then_default)


class StopSignals:
    """Install in the main thread, before ``rclpy.init``; ``arrived()`` after."""

    def __init__(self) -> None:
        self._seen = False
        self._stopping = False
        self.interrupting = True  # off while ROS callbacks run: the spin loop polls arrived()
        self._reader: socket.socket | None = None
        self._writer: socket.socket | None = None
        self._handlers: dict[int, object] = {}
        self._wakeup_fd = -1

    def install(self) -> StopSignals:
        if threading.current_thread() is not threading.main_thread():
            return self  # signals are the main thread's; rclpy.ok() is all there is
        self._reader, self._writer = socket.socketpair()
        self._reader.setblocking(False)
        self._writer.setblocking(False)
        for signum in STOPS:
            self._handlers[signum] = signal.getsignal(signum)
            signal.signal(signum, self._on_stop)
        self._wakeup_fd = signal.set_wakeup_fd(self._writer.fileno(), warn_on_full_buffer=False)
        return self

    def _on_stop(self, signum, frame) -> None:
        if self._stopping:  # launch's SIGTERM after its SIGINT: the stop is under way
            _once_then_default(signum, frame)
            return
        self._stopping = True
        if self.interrupting:
            raise KeyboardInterrupt

    def arrived(self) -> bool:
        if self._seen or self._reader is None:
            return self._seen
        try:
            while data := self._reader.recv(64):
                self._seen = self._seen or any(b in STOPS for b in data)
        except BlockingIOError:
            pass
        return self._seen

    def uninstall(self) -> None:
        if self._reader is None:
            return
        signal.set_wakeup_fd(self._wakeup_fd)
        for signum, handler in self._handlers.items():
            signal.signal(signum, handler)
        self._reader.close()
        self._writer.close()
        self._reader = self._writer = None
