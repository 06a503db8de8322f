"""exit_timer.exit_if_stuck: a process whose last step holds the GIL in C for good (Fast DDS's
participant deletion) ends with exit code 0 once the bound is over, after writing its Python
stacks; a step that ends in time changes nothing."""

import subprocess
import sys
import time

import pytest

pytestmark = pytest.mark.skipif(sys.platform != "linux", reason="POSIX timers: Linux")

STUCK = """
import ctypes
from dsr_graph.ros.exit_timer import exit_if_stuck
with exit_if_stuck({bound}, {code}):
    ctypes.PyDLL(None).sleep({sleep})  # PyDLL: the GIL is held for the whole call
print("after the block", flush=True)
"""


def run(bound: float, sleep: int, code: int = 0) -> tuple[subprocess.CompletedProcess, float]:
    started = time.monotonic()
    done = subprocess.run(
        [sys.executable, "-c", STUCK.format(bound=bound, sleep=sleep, code=code)],
        capture_output=True,
        text=True,
        timeout=120,
    )
    return done, time.monotonic() - started


def test_a_step_stuck_in_c_with_the_gil_ends_the_process_cleanly_with_its_stacks():
    done, took = run(bound=1.0, sleep=60)
    assert done.returncode == 0, done.stderr
    assert took < 30  # far less than the 60 s the step would have taken
    assert "after the block" not in done.stdout
    assert "Timeout" in done.stderr and "<string>" in done.stderr  # where it was stuck


def test_a_tool_that_failed_ends_with_its_own_code_when_its_goodbye_hangs():
    """``clarc start`` refused: its caller must still see the refusal (RosSession.stuck_exit)."""
    done, took = run(bound=1.0, sleep=60, code=1)
    assert done.returncode == 1 and took < 30 and "after the block" not in done.stdout


def test_a_step_that_ends_in_time_goes_on_as_before():
    done, _ = run(bound=30.0, sleep=0)
    assert done.returncode == 0 and "after the block" in done.stdout
    assert "Timeout" not in done.stderr
