"""ROS domains a process takes for itself, so that test runs, benchmarks and robots started by
``scripts/launch.sh`` on one machine never share one.

Domains 10 to 99 (clear of the usual 0; below 101, where Fast DDS's ports would reach Linux's
ephemeral ones) are cut into ``BLOCKS`` blocks of ``BLOCK``. A process takes a block by an
exclusive ``flock`` on ``<temp folder>/clarc-ros-domains/block-<n>.lock`` and holds it until it
ends (the lock goes with the last process holding its file open: a launch's nodes inherit it).
``scripts/launch.sh`` takes its block with the shell's ``flock`` on the same files, in the order
``python -m dsr_graph.ros.domains PID`` prints them.
"""

from __future__ import annotations

import fcntl
import os
import tempfile
from pathlib import Path
from typing import IO

BLOCK = 10  # domains in a block
BLOCKS = 9  # blocks: domains 10..99
FIRST = 10


def lock_folder() -> Path:
    return Path(tempfile.gettempdir()) / "clarc-ros-domains"


def candidates(pid: int) -> list[tuple[Path, int]]:
    """Each block's lock file and first domain, in the order process ``pid`` tries them (two
    runs started together try different blocks first)."""
    folder = lock_folder()
    folder.mkdir(exist_ok=True)
    order = [(pid + i) % BLOCKS for i in range(BLOCKS)]
    return [(folder / f"block-{b}.lock", FIRST + BLOCK * b) for b in order]


def reserve(blocks: int = 1) -> tuple[list[int], list[IO]]:
    """``blocks`` free blocks: (their domains in order, the lock files to keep open while they
    are used). ``RuntimeError`` naming the folder when too few are free."""
    domains: list[int] = []
    locks: list[IO] = []
    for path, first in candidates(os.getpid()):
        try:
            lock = open(path, "w")  # kept open by the caller: the lock lasts as long
        except OSError:  # another user's lock file: that block is theirs
            continue
        try:
            fcntl.flock(lock, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            lock.close()
            continue
        locks.append(lock)
        domains += range(first, first + BLOCK)
        if len(locks) == blocks:
            return domains, locks
    for lock in locks:
        lock.close()
    raise RuntimeError(
        f"fewer than {blocks} block(s) of ROS domains are free: the others are held by test "
        f"runs, benchmarks or launches on this machine ({lock_folder()})"
    )


if __name__ == "__main__":  # for scripts/launch.sh: "<lock file> <first domain>" a line
    import sys

    for path, first in candidates(int(sys.argv[1])):
        print(path, first)
