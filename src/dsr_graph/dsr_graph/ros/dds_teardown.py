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
goes on)."""

from __future__ import annotations

import os
from collections.abc import Iterator
from contextlib import contextmanager


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


def destroy_node(node) -> None:
    """``node.destroy_node()`` on one CPU (see the module's docstring)."""
    with one_cpu():
        node.destroy_node()
