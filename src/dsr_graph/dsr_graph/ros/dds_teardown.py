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

A participant Fast DDS has deadlocked already is not destroyed but abandoned (dds_deadlock.py)."""

from __future__ import annotations

import os
from collections.abc import Iterable, Iterator
from contextlib import contextmanager

from dsr_graph.ros.dds_deadlock import abandon, event_threads, stuck, threads


@contextmanager
def one_cpu() -> Iterator[None]:
    """Every thread of this process on one of its CPUs, for the duration."""
    before: dict[int, set[int]] = {}
    try:
        cpu = min(os.sched_getaffinity(0))
        for tid in threads():
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
