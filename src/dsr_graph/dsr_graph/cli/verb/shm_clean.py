"""Remove the shared-memory files Fast DDS's participants left when their processes died
outright (kill -9, a lost power supply): segments no process holds, older than a minute, and the
ports of the given ROS domains no process listens on, older than ten seconds. Unlike ``fastdds
shm clean`` it never takes a lock to test it, so it is safe beside robots starting in other
domains (ros/shm_zombies.py). Give only domains nothing else on this machine is starting in."""

from __future__ import annotations

import argparse
import sys

from dsr_graph.ros import shm_zombies

NAME = "shm-clean"
HELP = "remove Fast DDS shared-memory files of processes that died (safe beside living ones)"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument(
        "--domain",
        type=int,
        action="append",
        default=[],
        metavar="ID",
        help="a ROS domain whose dead ports go too (repeatable; default: segments only)",
    )


def run(args: argparse.Namespace) -> int:
    bad = [d for d in args.domain if not 0 <= d <= 232]
    if bad:
        print(f"dsr shm-clean: --domain {bad[0]}: a ROS domain is 0 to 232", file=sys.stderr)
        return 2
    removed = shm_zombies.clean(args.domain)
    print(f"removed {len(removed)} files of processes that died", file=sys.stderr)
    return 0
