"""dds_teardown.one_cpu: while a node is destroyed every thread of the process runs on one CPU
(Fast-DDS issue 6513's spin ends when the woken callback thread preempts the spinner there), and
each thread's CPUs are given back afterwards."""

import os
import threading

import pytest

from dsr_graph.ros.dds_teardown import one_cpu

pytestmark = pytest.mark.skipif(not hasattr(os, "sched_getaffinity"), reason="no CPU affinity")


def test_every_thread_runs_on_one_cpu_for_the_duration_and_gets_its_cpus_back():
    started, stop = threading.Event(), threading.Event()
    tids = []

    def worker():
        tids.append(threading.get_native_id())
        started.set()
        stop.wait(10)

    thread = threading.Thread(target=worker)
    thread.start()
    try:
        assert started.wait(10)
        main, other = threading.get_native_id(), tids[0]
        before = {tid: os.sched_getaffinity(tid) for tid in (main, other)}
        with one_cpu():
            inside = {tid: os.sched_getaffinity(tid) for tid in (main, other)}
        after = {tid: os.sched_getaffinity(tid) for tid in (main, other)}
    finally:
        stop.set()
        thread.join(10)
    cpu = min(before[main])
    assert inside == {main: {cpu}, other: {cpu}}
    assert after == before


def test_the_cpus_are_given_back_when_the_destruction_fails():
    before = os.sched_getaffinity(0)
    with pytest.raises(RuntimeError), one_cpu():
        raise RuntimeError("destroy failed")
    assert os.sched_getaffinity(0) == before
