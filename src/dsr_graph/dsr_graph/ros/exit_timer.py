"""A process's last step, bounded: if it has not ended within its time, the process exits
(code 0) from a thread that needs no GIL, after the stacks of its Python threads are written to
stderr.

A node's last step is deleting its DDS participant (dds_teardown), which in Fast DDS 2.14 can
wait for a discovery callback forever while holding the GIL: no Python thread, timer or signal
handler runs then, and ros2 launch escalates to SIGKILL after 15 s (seen in CI: kinect, at the end
of a Get Up & Go). By then the node has closed its files and flushed its logs; what is left
undone is only the goodbye to its peers, who drop the participant when its lease (2 s) ends.

The timer is POSIX ``timer_create`` with ``SIGEV_THREAD``: at expiry the C library starts a
thread that calls ``_exit`` with the timer's value (0). ``faulthandler`` writes the stacks a
moment before, also from a thread of its own. Where the C library has no such timer (not Linux),
only the stacks are written.
"""

from __future__ import annotations

import ctypes
import faulthandler
import os
import sys
from collections.abc import Iterator
from contextlib import contextmanager

CLOCK_MONOTONIC = 1
SIGEV_THREAD = 2
STACKS_BEFORE = 0.2  # seconds before the exit the stacks are written
TEARDOWN_LIMIT = 3.0  # seconds a process's DDS goodbye may take before it exits all the same


class _SigEvent(ctypes.Structure):  # struct sigevent (64 bytes on Linux, LP64)
    _fields_ = [
        ("value", ctypes.c_void_p),  # union sigval: the argument _exit gets
        ("signo", ctypes.c_int),
        ("notify", ctypes.c_int),
        ("function", ctypes.c_void_p),
        ("attributes", ctypes.c_void_p),
        ("_pad", ctypes.c_byte * 32),
    ]


class _TimeSpec(ctypes.Structure):
    _fields_ = [("sec", ctypes.c_long), ("nsec", ctypes.c_long)]


class _ITimerSpec(ctypes.Structure):
    _fields_ = [("interval", _TimeSpec), ("value", _TimeSpec)]


def _libc():
    try:
        libc = ctypes.CDLL(None, use_errno=True)
        libc.timer_create  # noqa: B018 (glibc 2.34+: in libc; older: librt)
        return libc
    except (OSError, AttributeError):
        try:
            return ctypes.CDLL("librt.so.1", use_errno=True)
        except OSError:
            return None


class CTimer:
    """A POSIX timer whose expiry calls a C function of one pointer argument from a thread the C
    library starts: it runs while Python is stuck holding the GIL. ``ok`` is False where there
    is no such timer (then start and stop do nothing)."""

    def __init__(self, function: int, argument: int | None = None):
        self._libc = _libc() if sys.platform == "linux" else None
        self._timer = ctypes.c_void_p()
        event = _SigEvent(value=argument, signo=0, notify=SIGEV_THREAD, function=function)
        self.ok = self._libc is not None and (
            self._libc.timer_create(CLOCK_MONOTONIC, ctypes.byref(event), ctypes.byref(self._timer))
            == 0
        )

    def start(self, seconds: float) -> bool:
        """(Re)arm: the call happens in ``seconds`` unless stopped first."""
        whole = int(seconds)
        return self._set(_TimeSpec(whole, int((seconds - whole) * 1e9)))

    def stop(self) -> None:
        self._set(_TimeSpec(0, 0))

    def close(self) -> None:
        if self.ok:
            self._libc.timer_delete(self._timer)
            self.ok = False

    def _set(self, value: _TimeSpec) -> bool:
        spec = _ITimerSpec(value=value)
        return self.ok and self._libc.timer_settime(self._timer, 0, ctypes.byref(spec), None) == 0


def c_function(name: str) -> int:
    """The address of a C library function, for a CTimer."""
    return ctypes.cast(getattr(ctypes.CDLL(None), name), ctypes.c_void_p).value


def _flush() -> None:
    for stream in (sys.stdout, sys.stderr):
        try:
            stream.flush()  # _exit flushes nothing
        except (OSError, ValueError):
            pass


def exit_now(code: int) -> None:
    """End the process at once with ``code``, what was printed flushed first (no teardown)."""
    _flush()
    os._exit(code)


@contextmanager
def exit_if_stuck(seconds: float, code: int = 0) -> Iterator[None]:
    """Run the block; if it is still running after ``seconds``, write the Python stacks to
    stderr and end the process with exit code ``code`` (see the module's docstring)."""
    _flush()
    faulthandler.dump_traceback_later(max(0.0, seconds - STACKS_BEFORE), exit=False)
    timer = CTimer(c_function("_exit"), code or None)
    if not timer.start(seconds):
        timer.close()
    try:
        yield
    finally:
        timer.close()
        faulthandler.cancel_dump_traceback_later()
