"""The crash-safe ``--dist loadfile`` scheduler (test/crash_safe_scheduling.py) step by step, with
stand-in workers: the order of events a loaded CI run met, which the system test
(test_crash_safe_scheduling.py) meets only now and then."""

from types import SimpleNamespace

from crash_safe_scheduling import CrashSafeLoadFileScheduling

COLLECTION = [f"test_{f}.py::test_{f}{n}" for f in "abcd" for n in (1, 2)]


class Worker:
    """What the scheduler uses of xdist's WorkerController: what it was sent."""

    def __init__(self, name):
        self.name = name
        self.gateway = SimpleNamespace(id=name)
        self.sent: list[list[int]] = []
        self.shutting_down = False

    def send_runtest_some(self, indices):
        self.sent.append(list(indices))

    def shutdown(self):
        self.shutting_down = True

    def __repr__(self):
        return self.name


def scheduler(workers):
    config = SimpleNamespace(
        getvalue=lambda name: [f"{len(workers)}*popen"] if name == "tx" else None,
        option=SimpleNamespace(loadscopereorder=False),
    )
    sched = CrashSafeLoadFileScheduling(config)
    for w in workers:
        sched.add_node(w)
        sched.add_node_collection(w, COLLECTION)
    sched.schedule()
    return sched


def test_a_replacement_not_collected_yet_is_given_nothing_when_another_worker_dies():
    gw0, gw1 = Worker("gw0"), Worker("gw1")
    sched = scheduler([gw0, gw1])
    # each holds two files; gw0 dies in its first test, and is replaced
    assert sched.remove_node(gw0) == "test_a.py::test_a1"
    gw2 = Worker("gw2")
    sched.add_node(gw2)
    # gw1 dies before gw2's collection is in: before the fix a file was popped for gw2 and the
    # KeyError on its collection left it recorded as gw2's, never sent
    assert sched.remove_node(gw1) == "test_b.py::test_b1"
    assert gw2.sent == [] and sched.assigned_work[gw2] == {}
    # once collected, gw2 runs every test left but those the dead died in, and is told the end
    sched.add_node_collection(gw2, COLLECTION)
    sched.schedule()
    ran = []
    while len(ran) < sum(map(len, gw2.sent)):
        index = [i for batch in gw2.sent for i in batch][len(ran)]
        ran.append(COLLECTION[index])
        sched.mark_test_complete(gw2, index)
    assert sorted(ran) == [
        t for t in COLLECTION if t not in ("test_a.py::test_a1", "test_b.py::test_b1")
    ]
    assert gw2.shutting_down and sched.tests_finished
