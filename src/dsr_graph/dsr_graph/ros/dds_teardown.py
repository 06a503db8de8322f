"""Destroying a node without Fast DDS 2.14's spin at its participant's deletion.

Deleting a participant (rclpy's destroy_node of the context's last node) first clears its
listener, waiting for a discovery callback in flight to end. In Fast DDS 2.14 that wait
busy-spins (Fast-DDS issue 6513: an infinite deadline that the condition variable turns into
one in the past), releasing and re-taking its mutex. Seen here with gdb at launches' shutdown,
when every peer leaves at once and each of their endpoints is a callback: the node's main thread
spinning in DomainParticipant::set_listener, a discovery callback's thread blocked on a mutex
(which one was not captured; the spinner's, by issue 6513's account), the node ignoring SIGINT
and SIGTERM (rclpy holds the GIL there) until launch killed it.

While the node is destroyed every thread of the process runs on one CPU: a thread woken when
the spinner releases the mutex then preempts it on that CPU and takes the mutex first, so the
callback ends and so does the wait. The threads' CPUs are put back afterwards (a test process
goes on).

A participant can also be deadlocked for good before its node is destroyed (Fast-DDS issue
6502, open, no release fixes it; caught here with gdb in a test process): a remote peer removes
one of its writers, and the discovery thread, holding the participant's PDP mutex, waits for
the event thread to be idle (``ResourceEvent::unregister_timer``) while the event thread, in
``PDP::check_remote_participant_liveliness``, waits for that mutex. Destroying anything of
that participant then waits for the event thread for ever, holding the GIL. An event thread
at rest waits for its next timer (a futex wait with a timeout); one that has waited on a lock
(a futex wait with none) without running for ``STALL`` seconds is deadlocked. Such a node is
not destroyed but abandoned: kept referenced for the life of the process, so that neither the
caller nor the interpreter's exit waits on it. Its peers drop it when its lease ends (it no
longer announces itself), and its resources go with the process."""

from __future__ import annotations

import ctypes
import os
import platform
import sys
import time
import warnings
from collections.abc import Iterable, Iterator
from contextlib import contextmanager

EVENT_THREAD = "dds.ev."  # the name Fast DDS gives each participant's event thread
# the futex system call's number as /proc/<pid>/task/<tid>/syscall gives it (None: unknown here,
# and no thread is ever taken as deadlocked)
FUTEX = {"x86_64": 202, "aarch64": 98}.get(platform.machine())
STALL = 2.0  # seconds an event thread may wait on a lock before it counts as deadlocked


def _threads() -> list[int]:
    try:
        return [int(tid) for tid in os.listdir("/proc/self/task")]
    except OSError:  # not Linux: nothing to do
        return []


@contextmanager
def one_cpu() -> Iterator[None]:
    """Every thread of this process on one of its CPUs, for the duration."""
    before: dict[int, set[int]] = {}
    try:
        cpu = min(os.sched_getaffinity(0))
        for tid in _threads():
            try:
                before[tid] = os.sched_getaffinity(tid)
                os.sched_setaffinity(tid, {cpu})
            except OSError:  # the thread has ended meanwhile
                pass
    except (AttributeError, OSError, ValueError):  # no affinity on this platform
        pass
    try:
        yield
    finally:
        for tid, cpus in before.items():
            try:
                os.sched_setaffinity(tid, cpus)
            except OSError:
                pass


def _read(tid: int, name: str) -> str:
    try:
        with open(f"/proc/self/task/{tid}/{name}") as file:
            return file.read().strip()
    except OSError:  # the thread has ended, or no /proc (not Linux)
        return ""


def event_threads() -> set[int]:
    """The ids of this process's Fast DDS event threads (one per participant)."""
    return {tid for tid in _threads() if _read(tid, "comm").startswith(EVENT_THREAD)}


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


_abandoned: list[object] = []


def abandon(objects: Iterable[object], jammed: list[int]) -> None:
    """Keep ``objects`` (a node, its context, ...) for the life of the process, undestroyed, and
    say so on stderr and as a warning. The extra references are never given back, so that the
    interpreter's exit does not destroy them either."""
    for item in objects:
        _abandoned.append(item)
        ctypes.pythonapi.Py_IncRef(ctypes.py_object(item))
    message = (
        f"a DDS participant of this process is deadlocked in Fast DDS (event thread(s) "
        f"{', '.join(map(str, jammed))} stuck on a lock for {STALL:g} s: Fast-DDS issue 6502); "
        "its node is left undestroyed, and its peers drop it when its lease ends"
    )
    print(f"dds_teardown: {message}", file=sys.stderr, flush=True)
    warnings.warn(message, RuntimeWarning, stacklevel=3)


def destroy_node(node, event_tids: Iterable[int] | None = None, also: Iterable = ()) -> bool:
    """``node.destroy_node()`` on one CPU (see the module's docstring); if the participant's
    event thread (``event_tids``; None: every one of the process) is deadlocked, the node and
    ``also`` (its context, executor) are abandoned instead: False."""
    jammed = stuck(event_threads() if event_tids is None else event_tids)
    if jammed:
        abandon([node, *also], jammed)
        return False
    with one_cpu():
        node.destroy_node()
    return True


@contextmanager
def new_event_threads() -> Iterator[set[int]]:
    """The event threads started during the block (a participant created there): the set is
    filled when the block ends."""
    before = event_threads()
    found: set[int] = set()
    yield found
    found.update(event_threads() - before)
