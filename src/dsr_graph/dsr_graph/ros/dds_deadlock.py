"""Telling a DDS participant that Fast DDS has deadlocked for good, and what to do with it.

A participant can be deadlocked for good by Fast DDS 2.14 (Fast-DDS issue 6502, open, no
release fixes it; caught here with gdb in a test process): a remote peer removes
one of its writers, and the discovery thread, holding the participant's PDP mutex, waits for
the event thread to be idle (``ResourceEvent::unregister_timer``) while the event thread, in
``PDP::check_remote_participant_liveliness``, waits for that mutex. Destroying anything of
that participant then waits for the event thread for ever, holding the GIL. An event thread
at rest waits for its next timer (a futex wait with a timeout); one that has waited on a lock
(a futex wait with none) without running for ``STALL`` seconds is deadlocked. Its node is not
destroyed (dds_teardown) but abandoned: kept referenced for the life of the process, so that
the caller does not wait on it. The interpreter's exit still would (Fast DDS's own teardown
destroys every participant): a program that abandoned one should end with
``exit_timer.exit_now`` (``any_abandoned``; the benchmark does). Its peers drop it when its
lease ends (it no longer announces itself), and its resources go with the process.

A node process does not wait for its stop to find it: ``watch`` looks every second, and the node
exits (run_node) to be restarted by its launch, as a deadlocked participant no longer announces
itself and its peers have dropped it: a node alive but cut off from every other.
"""

from __future__ import annotations

import ctypes
import itertools
import os
import platform
import sys
import threading
import time
import warnings
from collections.abc import Callable, Iterable, Iterator
from contextlib import contextmanager

EVENT_THREAD = "dds.ev."  # the name Fast DDS gives each participant's event thread
# the futex system call's number as /proc/<pid>/task/<tid>/syscall gives it (None: unknown here,
# and no thread is ever taken as deadlocked)
FUTEX = {"x86_64": 202, "aarch64": 98}.get(platform.machine())
STALL = 2.0  # seconds an event thread may wait on a lock before it counts as deadlocked
ISSUE = "Fast-DDS issue 6502"
RESCAN = 10  # watch's turns between two looks for the process's event threads (all its threads)


def threads() -> list[int]:
    """The ids of this process's threads (none where there is no /proc: not Linux)."""
    try:
        return [int(tid) for tid in os.listdir("/proc/self/task")]
    except OSError:
        return []


def _read(tid: int, name: str) -> str:
    try:
        with open(f"/proc/self/task/{tid}/{name}") as file:
            return file.read().strip()
    except OSError:  # the thread has ended, or no /proc (not Linux)
        return ""


def event_threads() -> set[int]:
    """The ids of this process's Fast DDS event threads (one per participant)."""
    return {tid for tid in threads() if _read(tid, "comm").startswith(EVENT_THREAD)}


def _waits_on_a_lock(tid: int) -> bool:
    # /proc/.../syscall: the call's number, its six arguments, ...; a futex wait's fourth
    # argument is its timeout (0: none). A thread that is running says "running".
    fields = _read(tid, "syscall").split()
    return FUTEX is not None and len(fields) > 4 and fields[0] == str(FUTEX) and fields[4] == "0x0"


def _run_time(tid: int) -> str:
    return _read(tid, "schedstat").split(" ")[0]


def stuck(tids: Iterable[int], stall: float = STALL) -> list[int]:
    """The threads among ``tids`` that wait on a lock and have not run for ``stall`` seconds
    (checked for at most that long; at once for threads at rest or running)."""
    suspects = {tid: _run_time(tid) for tid in tids if _waits_on_a_lock(tid)}
    deadline = time.monotonic() + stall
    while suspects and time.monotonic() < deadline:
        time.sleep(0.02)
        for tid, ran in list(suspects.items()):
            if not _waits_on_a_lock(tid) or _run_time(tid) != ran:
                del suspects[tid]
    return sorted(suspects)


def describe(jammed: list[int], stall: float = STALL) -> str:
    """What a deadlock found in ``jammed`` (event thread ids) is, for a log line."""
    return (
        f"Fast DDS has deadlocked a DDS participant of this process (event thread(s) "
        f"{', '.join(map(str, jammed))} stuck on a lock for {stall:g} s: {ISSUE})"
    )


_abandoned: list[object] = []


def any_abandoned() -> bool:
    """Whether this process abandoned a participant: it must end with ``exit_timer.exit_now``,
    since the interpreter's exit runs Fast DDS's own teardown, which waits on it for ever (a
    benchmark run that had printed its report hung so)."""
    return bool(_abandoned)


def abandon(objects: Iterable[object], jammed: list[int]) -> None:
    """Keep ``objects`` (a node, its context, ...) for the life of the process, undestroyed, and
    say so on stderr and as a warning. The extra references are never given back, so that the
    interpreter's exit does not destroy them either."""
    for item in objects:
        _abandoned.append(item)
        ctypes.pythonapi.Py_IncRef(ctypes.py_object(item))
    message = (
        f"{describe(jammed)}; its node is left undestroyed, and its peers drop it when its "
        "lease ends"
    )
    print(f"dds_deadlock: {message}", file=sys.stderr, flush=True)
    warnings.warn(message, RuntimeWarning, stacklevel=3)


def watch(
    on_stuck: Callable[[list[int]], None],
    tids: Iterable[int] | None = None,
    period: float = 1.0,
    stall: float = STALL,
) -> threading.Thread:
    """A daemon thread that calls ``on_stuck`` (once) when one of ``tids`` (None: every event
    thread of the process) has waited on a lock for ``stall`` seconds without running."""

    def run() -> None:
        watched = set(tids) if tids is not None else set()
        for turn in itertools.count():
            time.sleep(period)
            if tids is None and turn % RESCAN == 0:  # a participant made later is watched too
                watched = event_threads()
            jammed = stuck(watched, stall)
            if jammed:
                on_stuck(jammed)
                return

    thread = threading.Thread(target=run, name="dds_deadlock.watch", daemon=True)
    thread.start()
    return thread


@contextmanager
def new_event_threads() -> Iterator[set[int]]:
    """The event threads started during the block (a participant created there): the set is
    filled when the block ends."""
    before = event_threads()
    found: set[int] = set()
    yield found
    found.update(event_threads() - before)
