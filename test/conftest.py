"""Shared test helpers. The suite runs inside `source scripts/env.sh` (scripts/test.sh does it)."""

import ctypes
import os
import shutil
import sys
from pathlib import Path

import pytest
from crash_safe_scheduling import pytest_xdist_make_scheduler  # noqa: F401 (a hook: registered)
from hypothesis import settings

from dsr_graph.ros.exit_timer import CTimer, c_function

# CI explores a fixed set of examples (reproducible); a developer's run explores new ones.
settings.register_profile("ci", derandomize=True, print_blob=True)
settings.register_profile("dev", print_blob=True)
settings.load_profile("ci" if os.environ.get("CI") else "dev")

REPO = Path(__file__).resolve().parent.parent
# CI clones the repo with shared/ beside it; a developer tree has it at ../shared too.
SHARED = Path(os.environ.get("DSR_SHARED", REPO.parent / "shared"))
CORTEX_WORLDS = SHARED / "data" / "cortex_worlds"
MOTION = SHARED / "data" / "motion"
SPEECH = SHARED / "data" / "speech"
_watch_fd = pytest.StashKey[int]()
_native_stacks = pytest.StashKey[CTimer | None]()


def unavailable(why: str) -> None:
    """What a test needs is not on this machine: skipped, saying why (a user's clone has no
    ../shared beside it), failed under CI (which always has it)."""
    if os.environ.get("CI"):
        pytest.fail(why)
    pytest.skip(why)


def shared_folder(path: Path, what: str) -> Path:
    """A folder of ../shared."""
    if not path.is_dir():
        unavailable(f"{what} not found at {path} (../shared is absent; set DSR_SHARED)")
    return path


# pytest-timeout's signal reaches a test only between Python bytecodes: one stuck inside C (a
# DDS deadlock in a teardown: Fast-DDS issue 6502) would hang the run until CI's limit. Each
# phase of a test is also watched by faulthandler's C thread, which prints every thread's stack
# and ends the worker MARGIN seconds after the test's timeout (the test fails as the worker's
# crash and the run goes on: crash_safe_scheduling.py).
# (test_watchdog.py sets a shorter margin for a suite of its own.)
MARGIN = float(os.environ.get("DSR_TEST_WATCH_MARGIN", "120"))
# ... and, a third of the margin before that, gdb writes every thread's native stack there too:
# the lock a stuck DDS call waits on, which Python's stacks do not show.
NATIVE_BEFORE = MARGIN / 3
LOG_TAIL = 40  # lines of each ROS process's log shown with a failed test


def pytest_configure(config):
    config.stash[_watch_fd] = os.dup(sys.stderr.fileno())  # pytest's own stderr, not a test's
    config.stash[_native_stacks] = native_stacks_timer(config.stash[_watch_fd])


def native_stacks_timer(fd: int):
    """A timer that runs gdb on this process from a C thread (Python may be stuck holding the
    GIL); None without gdb."""
    gdb = shutil.which("gdb")
    if gdb is None:
        return None
    out = f"/proc/{os.getpid()}/fd/{fd}"  # a dup'ed fd is not inherited: its path is
    command = ctypes.create_string_buffer(
        f"echo '--- native stacks (gdb) ---' >> {out}; timeout 30 {gdb} -p {os.getpid()} "
        f"-batch -nx -ex 'thread apply all bt' >> {out} 2>&1".encode()
    )
    timer = CTimer(c_function("system"), ctypes.addressof(command))
    timer.command = command  # the C string lives as long as the timer
    return timer if timer.ok else None


def pytest_unconfigure(config):
    import faulthandler

    faulthandler.cancel_dump_traceback_later()
    if config.stash[_native_stacks] is not None:
        config.stash[_native_stacks].close()
    os.close(config.stash[_watch_fd])


@pytest.hookimpl(wrapper=True, tryfirst=True)
def pytest_runtest_protocol(item):
    import faulthandler

    try:
        return (yield)
    finally:
        faulthandler.cancel_dump_traceback_later()
        if item.config.stash[_native_stacks] is not None:
            item.config.stash[_native_stacks].stop()


@pytest.hookimpl(wrapper=True)
def pytest_runtest_makereport(item, call):
    """A failed test that started ROS processes shows the end of each one's log: a failure in CI
    then says what the server and the agents were doing (their folders do not outlive the run)."""
    report = yield
    world = getattr(item, "funcargs", {}).get("ros")
    if report.when == "call" and report.failed and isinstance(world, RosWorld):
        report.sections.append(("the test's ROS processes", world.procs.tails(LOG_TAIL)))
    return report


def _watch(item) -> None:
    """(Re)arm the watch for a phase: pytest's faulthandler plugin cancels it when a test fails,
    before the teardown that may be the one to hang."""
    import faulthandler

    marker = item.get_closest_marker("timeout")
    limit = item.config.getini("timeout")
    if marker is not None:
        limit = marker.args[0] if marker.args else marker.kwargs.get("timeout", limit)
    faulthandler.dump_traceback_later(
        float(limit) + MARGIN, exit=True, file=item.config.stash[_watch_fd]
    )
    if item.config.stash[_native_stacks] is not None:
        item.config.stash[_native_stacks].start(float(limit) + MARGIN - NATIVE_BEFORE)


def pytest_collection_modifyitems(config, items):
    """Every test under test/unit is a ``unit`` test (no ROS, no processes): with the ``smoke``
    tests, scripts/test.sh --quick runs those (``-m "unit or smoke"``)."""
    unit = REPO / "test" / "unit"
    for item in items:
        if unit in item.path.parents:
            item.add_marker(pytest.mark.unit)


@pytest.hookimpl(tryfirst=True)
def pytest_runtest_setup(item):
    _watch(item)


@pytest.hookimpl(tryfirst=True)
def pytest_runtest_call(item):
    _watch(item)


@pytest.hookimpl(tryfirst=True)
def pytest_runtest_teardown(item):
    _watch(item)


@pytest.fixture
def cortex_dir():
    """../shared's CORTEX worlds."""
    return shared_folder(CORTEX_WORLDS, "shared CORTEX worlds")


@pytest.fixture
def speech_dir():
    """../shared's real speech recordings."""
    return shared_folder(SPEECH, "shared speech recordings")


def needs_espeak() -> None:
    """The voices of --audio: espeak-ng (Debian; scripts/setup.sh installs it as root)."""
    import shutil

    if shutil.which("espeak-ng") is None:
        unavailable("espeak-ng is not installed (apt-get install espeak-ng)")


@pytest.fixture
def motion_dir():
    """../shared's real recorded motion."""
    return shared_folder(MOTION, "shared recorded motion")


@pytest.fixture(scope="session")
def ros2_cli():
    """The ros2 command line and launch: a system ROS's, or those scripts/setup.sh installed from
    ../shared/vendor/ros2-jazzy."""
    import importlib.util
    import shutil

    if shutil.which("ros2") is None or importlib.util.find_spec("launch_ros") is None:
        unavailable(
            "no ros2 command line or launch_ros: no system ROS, and scripts/setup.sh found no "
            f"{SHARED / 'vendor' / 'ros2-jazzy'} to install them from (set DSR_ROS2_VENDOR)"
        )


class RosWorld:
    """Processes started by a test plus an in-test ROS session, all in one fresh ROS domain."""

    def __init__(self, tmp_path):
        from ros_processes import Processes, fresh_domain_id, new_session

        self.domain_id = fresh_domain_id()
        self.procs = Processes(tmp_path, self.domain_id)
        self.session = new_session(self.domain_id)
        self.tmp = tmp_path

    def close(self):
        # the session leaves DDS first, while the processes it talks to are alive: destroying
        # an entity while a remote participant's lease runs out (the processes just stopped)
        # can deadlock Fast DDS 2.14 for good (Fast-DDS issue 6502)
        try:
            self.session.close()
        finally:
            self.procs.stop_all()


@pytest.fixture
def ros(tmp_path):
    world = RosWorld(tmp_path)
    try:
        yield world
    finally:
        world.close()


@pytest.fixture(scope="session")
def default_run(tmp_path_factory):
    """The default Barthel scenario through ``scripts/launch.sh --record``, once for the
    session: its result (test_barthel_scenarios.py) and its recording (test_recording.py) are
    checked from the one run. (the folder: run.mcap, cgamed.sqlite, run/; the finished launch)"""
    from ros_processes import EPHEMERAL_PORTS, run_robot

    tmp = tmp_path_factory.mktemp("default_run")
    run = run_robot(
        "launch.sh",
        "--scenario",
        REPO / "scenarios" / "default.yaml",
        "--record",
        tmp / "run.mcap",
        "--db",
        tmp / "cgamed.sqlite",
        "--timeout",
        "150",
        *EPHEMERAL_PORTS,
        run_dir=tmp / "run",
    )
    return tmp, run


@pytest.fixture(autouse=True, scope="module")
def shared_memory_of_killed_processes(request):
    """After each module of system tests, Fast DDS's shared-memory files that processes killed
    outright (kill -9 in the crash tests) left are removed: a stale port's lock can make a later
    participant of the same domain wait forever at start (Fast-DDS issues 1144, 6117). Only the
    ports of this worker's own domains, where nothing runs between its tests, and dead segments:
    ``fastdds shm clean`` takes every lock to test it, and a participant locking its port at that
    moment fails to open it (dsr_graph/ros/shm_zombies.py)."""
    yield
    if "system" in Path(str(request.path)).parts:
        from dsr_graph.ros import shm_zombies

        from ros_processes import own_domains

        shm_zombies.clean(own_domains())
