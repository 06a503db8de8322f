"""dds_deadlock.stuck and watch, dds_teardown.destroy_node: a participant whose event thread
waits on a lock for good (Fast-DDS issue 6502) is told by the watch and abandoned, not destroyed
(destroying it would wait for ever holding the GIL); an event thread at rest (a timed wait),
running, or waiting on a lock that comes free is not taken as deadlocked."""

import ctypes
import threading
import time

import pytest

from dsr_graph.ros import dds_deadlock, dds_teardown

pytestmark = pytest.mark.skipif(
    dds_deadlock.FUTEX is None or not dds_deadlock.threads(),
    reason="no /proc task files or unknown futex call number on this machine",
)


class Thread:
    """A thread named like Fast DDS's event thread that runs ``body`` once started."""

    def __init__(self, body):
        self.ready, self.tid = threading.Event(), 0

        def run():
            ctypes.CDLL(None).prctl(15, b"dds.ev.test")  # PR_SET_NAME
            self.tid = threading.get_native_id()
            self.ready.set()
            body()

        self.thread = threading.Thread(target=run, daemon=True)
        self.thread.start()
        assert self.ready.wait(10)
        time.sleep(0.1)  # into its wait


def test_a_thread_waiting_on_a_lock_that_never_comes_free_is_stuck():
    lock = threading.Lock()
    lock.acquire()
    blocked = Thread(lock.acquire)
    try:
        assert blocked.tid in dds_deadlock.event_threads()
        assert dds_deadlock.stuck([blocked.tid], stall=0.3) == [blocked.tid]
    finally:
        lock.release()
        blocked.thread.join(10)


def test_threads_at_rest_running_or_briefly_blocked_are_not_stuck():
    stop = threading.Event()
    lock = threading.Lock()
    lock.acquire()
    at_rest = Thread(lambda: stop.wait(30))  # a timed wait, as for the next timer

    def spin():
        while not stop.is_set():
            pass

    busy = Thread(spin)
    briefly = Thread(lock.acquire)
    threading.Timer(0.2, lock.release).start()
    try:
        started = time.monotonic()
        assert dds_deadlock.stuck([at_rest.tid, busy.tid, briefly.tid], stall=3.0) == []
        assert time.monotonic() - started < 2.0  # decided as soon as the lock came free
    finally:
        stop.set()
        for thread in (at_rest, busy, briefly):
            thread.thread.join(10)


def test_a_deadlocked_participant_s_node_is_abandoned_not_destroyed(recwarn):
    class Node:
        destroyed = False

        def destroy_node(self):
            self.destroyed = True

    lock = threading.Lock()
    lock.acquire()
    blocked = Thread(lock.acquire)
    jammed, healthy = Node(), Node()
    try:
        assert dds_teardown.destroy_node(jammed, [blocked.tid]) is False
        assert dds_teardown.destroy_node(healthy, []) is True
    finally:
        lock.release()
        blocked.thread.join(10)
    assert not jammed.destroyed and healthy.destroyed
    assert jammed in dds_deadlock._abandoned and dds_deadlock.any_abandoned()
    assert any("Fast-DDS issue 6502" in str(w.message) for w in recwarn)


def test_the_watch_tells_of_a_deadlock_once():
    lock = threading.Lock()
    lock.acquire()
    blocked = Thread(lock.acquire)
    told = []
    try:
        watcher = dds_deadlock.watch(told.append, [blocked.tid], period=0.1)
        watcher.join(10)
        assert not watcher.is_alive() and told == [[blocked.tid]]
    finally:
        lock.release()
        blocked.thread.join(10)


CUT_OFF = """
import ctypes, threading, time
from dsr_graph.ros import dsr_node

class Logger:
    def fatal(self, text):
        print("FATAL", text, flush=True)

class Node:  # what _cut_off uses of a DsrNode
    def get_logger(self):
        return Logger()
    def stop_requested(self):
        return {stopping}

lock = threading.Lock()
lock.acquire()
def event_thread():
    ctypes.CDLL(None).prctl(15, b"dds.ev.0")
    lock.acquire()
threading.Thread(target=event_thread, daemon=True).start()
dsr_node.WATCH_STALL = 0.5
from dsr_graph.ros import dds_deadlock
dds_deadlock.watch(dsr_node._cut_off(Node()), period=0.1, stall=0.5)
time.sleep(3)
print("still running", flush=True)
"""


@pytest.mark.parametrize("stopping", [False, True])
def test_a_running_node_whose_participant_is_deadlocked_ends_to_be_restarted(stopping):
    import subprocess
    import sys

    done = subprocess.run(
        [sys.executable, "-c", CUT_OFF.format(stopping=stopping)],
        capture_output=True,
        text=True,
        timeout=120,
    )
    if stopping:  # a stop under way: its teardown leaves the participant, exit code its own
        assert done.returncode == 0 and "still running" in done.stdout, done.stderr
    else:
        assert done.returncode == 4, done.stdout + done.stderr
        assert "FATAL Fast DDS has deadlocked" in done.stdout and "6502" in done.stdout
        assert "still running" not in done.stdout
