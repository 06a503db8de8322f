"""ROS domains a process takes for itself (dsr_graph/ros/domains.py): blocks held by a lock file,
whether taken in Python (test runs, benchmarks) or by the shell's flock (scripts/launch.sh)."""

import os
import subprocess
import sys
import time

import pytest

from dsr_graph.ros import domains


@pytest.fixture
def locks(tmp_path, monkeypatch):
    folder = tmp_path / "clarc-ros-domains"
    monkeypatch.setattr(domains, "lock_folder", lambda: folder)
    return folder


def test_two_reservations_never_share_a_domain_and_a_released_block_is_free_again(locks):
    first, held = domains.reserve()
    second, other = domains.reserve(2)  # other: its locks, held to the end
    assert len(first) == domains.BLOCK and len(second) == 2 * domains.BLOCK
    assert not set(first) & set(second)
    assert all(10 <= d <= 99 for d in first + second)
    for lock in held:
        lock.close()
    again, _ = domains.reserve(domains.BLOCKS - 2)  # every block but the two still held
    assert set(first) <= set(again)
    with pytest.raises(RuntimeError, match="fewer than 1 block"):
        domains.reserve()


def test_a_block_the_shell_holds_is_not_taken(locks):
    """launch.sh takes its block with flock(1) on a file of ``candidates``: Python sees it held."""
    path, first = domains.candidates(os.getpid())[0]
    shell = subprocess.Popen(["flock", str(path), "sleep", "30"])  # waits for it if need be
    try:
        deadline = time.monotonic() + 10
        while True:  # until the shell holds it (a try of ours may take it first, and let go)
            taken, held = domains.reserve()
            for lock in held:
                lock.close()
            if first not in taken or time.monotonic() > deadline:
                break
            time.sleep(0.05)
        assert first not in taken
    finally:
        shell.kill()
        shell.wait()


def test_the_shell_reads_the_candidates_from_the_module(tmp_path):
    """What launch.sh reads: "<lock file> <first domain>" a block, in the order it tries them."""
    env = dict(os.environ, TMPDIR=str(tmp_path))
    out = subprocess.run(
        [sys.executable, "-m", "dsr_graph.ros.domains", "7"],
        capture_output=True,
        text=True,
        check=True,
        env=env,
    ).stdout.splitlines()
    assert len(out) == domains.BLOCKS
    path, first = out[0].split()
    assert path == str(tmp_path / "clarc-ros-domains" / f"block-{7 % domains.BLOCKS}.lock")
    assert int(first) == 10 + 10 * (7 % domains.BLOCKS)
