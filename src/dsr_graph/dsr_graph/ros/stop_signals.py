"""Whether SIGINT or SIGTERM has arrived, known from the instant it did.

rclpy's handler shuts the context down from a thread of its own, so an exception the signal
causes in the main thread can come before ``rclpy.ok()`` turns false. Seen at launches' closing
SIGINT: the KeyboardInterrupt raised inside a message's conversion comes out of rclpy's
``take_message`` as pybind's "RuntimeError: Unable to convert call argument '0'", which looked
like a crash (exit 1). Python's own C handler writes the signal's number to the wakeup fd
before it returns, and rclpy calls the handler that was there before ``rclpy.init``, so the
byte is in the socket before anything the signal causes.
"""

from __future__ import annotations

import signal
import socket
import threading

STOPS = (signal.SIGINT, signal.SIGTERM)


def _once_then_default(signum, _frame) -> None:
    # rclpy's handler, which ran first, is stopping the node; a second one ends the process
    # as the signal's default action would have without us.
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
    """Install before ``rclpy.init`` (rclpy chains to what it finds); ``arrived()`` after."""

    def __init__(self) -> None:
        self._seen = False
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
            handler = signal.getsignal(signum)
            if not callable(handler):  # SIG_DFL or SIG_IGN: no Python handler, no wakeup byte
                self._handlers[signum] = handler
                signal.signal(signum, _once_then_default)
        self._wakeup_fd = signal.set_wakeup_fd(self._writer.fileno(), warn_on_full_buffer=False)
        return self

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
