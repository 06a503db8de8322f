"""The DSR benchmarks, each figure next to a plain-rclpy (or naive numpy) baseline measured in the
same run. Run through scripts/bench.sh; writes a JSON report and prints a table.

Sections: latency (change-to-visible over two hops: a symbolic change, journalled by a group commit
after it is broadcast, and a volatile one, next to a raw rclpy relay and the fdatasync of a journal
line on this disk), throughput (1/4/8 subscribed agents, single ops and batches), scale
(1k/10k/100k nodes: cost per op, snapshot to a late joiner, memory), restart (an agent killed and
respawned at once: how soon it is in sync and has a change accepted), kinematics (transform queries
on trees of depth 2/10/50, cold and cached), barthel (a fast test: wall time and CPU seconds per
process), gug (a patient's skeleton streamed through the DSR at 30 Hz, 14 joints, as Person writes
it: the server's CPU, frames written of those offered, a Speech-sized change's latency and the
journal's growth, each against the same without the stream, quiet and with every core kept busy; a
whole Get Up & Go run's CPU against the Barthel run's; in a full run, every shipped GUG scenario
through launch.sh, quiet and loaded), camera (640x480 colour and depth images at 30 Hz beside the
skeleton: the server's CPU, images offered, written and delivered whole to another process's
replica, a Speech change's latency against the quiet figure, and what one hop costs a frame as
base64 JSON or as blobs), signed (what signing the DSR's traffic costs: latency, throughput with
one agent and the Barthel run's CPU, with DSR_SECURITY=enforce next to off), gc (a snapshot encoded
and loaded with the DSR processes' collector policy next to CPython's default thresholds, in
interleaved rounds).

Each ratio (DSR against the raw relay, volatile against raw, streaming against quiet, enforce
against off) is measured in interleaved rounds and reported under ``ratios`` as the median of the
per-round ratios with their spread (rounds.py). Each section is a module of its own beside this
one; one that fails is named under ``failed`` and the others still run (exit 1).
"""

from __future__ import annotations

import argparse
import importlib
import json
import os
import platform
import signal
import subprocess
import sys
import tempfile
import time
import traceback
from pathlib import Path
from typing import Any

from barthel import bench_barthel
from camera import bench_camera
from gug import bench_gug
from harness import ROOT
from kinematics import bench_kinematics
from latency import bench_latency, bench_server_against
from restart import bench_restart
from scale import bench_scale, build_world
from signed import bench_signed
from tables import table
from throughput import bench_throughput

from dsr_graph.ros import dds_deadlock
from dsr_graph.ros.domains import reserve as reserve_domains
from dsr_graph.ros.exit_timer import exit_now


def lazy(module: str, name: str):
    """A section's function imported when it runs (speech loads the recognisers)."""
    return lambda *args: getattr(importlib.import_module(module), name)(*args)


bench_provenance, bench_rt_history = (
    lazy("cortex", "bench_provenance"),
    lazy("cortex", "bench_rt_history"),
)
bench_gc_policy = lazy("gc_policy", "bench_gc_policy")
bench_speech, bench_speech_loop = (
    lazy("speech", "bench_speech"),
    lazy("speech", "bench_speech_loop"),
)


SECTIONS = (
    "kinematics",
    "latency",
    "throughput",
    "scale",
    "restart",
    "barthel",
    "gug",
    "camera",
    "provenance",
    "rt_history",
    "gc",
    "speech",
    "speech_loop",
    "signed",
    "baseline",
)


def source_tree(rev: str, work: Path) -> Path:
    """The project's files at git revision ``rev``, in a folder of ``work``."""
    tree = work / f"baseline_{rev.replace('/', '_')}"
    tree.mkdir()
    archive = subprocess.run(
        ["git", "-C", str(ROOT), "archive", rev, "src"], capture_output=True, check=True
    )
    subprocess.run(["tar", "-x", "-C", str(tree)], input=archive.stdout, check=True)
    return tree


def save(report: dict[str, Any], out: Path) -> None:
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text(json.dumps(report, indent=2))


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument(
        "--quick",
        action="store_true",
        help="fewer samples, sizes up to 10k, 1 and 8 agents, a Barthel run at pace x0.05, "
        "no Get Up & Go scenarios, two voices for speech",
    )
    parser.add_argument("--out", default=str(ROOT / "bench-results" / "bench.json"))
    parser.add_argument(
        "--baseline",
        metavar="REV",
        help="also run section 'baseline': this tree's server against the server of git "
        "revision REV, side by side, a change's latency in interleaved rounds",
    )
    parser.add_argument(
        "--only",
        nargs="*",
        metavar="SECTION",
        help=f"sections to run: {', '.join(SECTIONS)} (default all)",
    )
    args = parser.parse_args()
    # a SIGTERM (timeout, CI) unwinds like Ctrl-C: each section's processes are stopped on the
    # way out, not left running in their own sessions
    signal.signal(signal.SIGTERM, lambda signum, frame: sys.exit(128 + signum))
    quick = args.quick
    # ROS domains of our own, two a section, held until the run ends (no test run or launch on
    # this machine takes them: ros/domains.py)
    domains, _held = reserve_domains(3)
    failed: dict[str, str] = {}
    report: dict[str, Any] = {
        "machine": {
            "cpus": os.cpu_count(),
            "python": platform.python_version(),
            "platform": platform.platform(),
            "cpu": next(
                (
                    line.split(":", 1)[1].strip()
                    for line in open("/proc/cpuinfo")
                    if line.startswith("model name")
                ),
                "",
            ),
        },
        "mode": "quick" if quick else "full",
        "when": time.strftime("%Y-%m-%dT%H:%M:%S%z"),
        "ratios": {},
        "failed": failed,  # section -> why
    }
    out = Path(args.out)
    rounds = 10  # interleaved rounds of each ratio's sides (rounds.py)
    with tempfile.TemporaryDirectory() as tmp:
        work = Path(tmp)
        sections_run = [
            ("kinematics", lambda d: bench_kinematics([2, 10, 50], 2000 if quick else 20000)),
            ("latency", lambda d: bench_latency(work, d, rounds, 200 if quick else 300)),
            (
                "throughput",
                lambda d: bench_throughput(
                    work, d, rounds, 1000 if quick else 2000, 100, [1, 8] if quick else [1, 4, 8]
                ),
            ),
            (
                "scale",
                lambda d: bench_scale(
                    work,
                    d,
                    [1000, 10000] if quick else [1000, 10000, 100000],
                    2000 if quick else 10000,
                ),
            ),
            ("restart", lambda d: bench_restart(work, d, 5 if quick else 10)),
            ("barthel", lambda d: bench_barthel(work, 0.05 if quick else 0.1)),
            (
                "gug",
                lambda d: bench_gug(
                    work,
                    d,
                    5.0 if quick else 20.0,
                    rounds,
                    100 if quick else 300,
                    0.1,
                    not quick,
                ),
            ),
            (
                "camera",
                lambda d: bench_camera(
                    work, d, 5.0 if quick else 20.0, rounds, 100 if quick else 300
                ),
            ),
            (
                "provenance",
                lambda d: bench_provenance(
                    build_world, [10000] if quick else [10000, 100000], 2000 if quick else 10000
                ),
            ),
            ("rt_history", lambda d: bench_rt_history([2, 10, 50], 2000 if quick else 20000)),
            ("gc", lambda d: bench_gc_policy(10000 if quick else 100000, 5 if quick else 10)),
            ("speech", lambda d: bench_speech(quick)),
            ("speech_loop", lambda d: bench_speech_loop(work, d, ROOT)),
            (
                "signed",
                lambda d: bench_signed(
                    work, d, rounds, 100 if quick else 300, 1000 if quick else 5000, 0.1
                ),
            ),
            (
                "baseline",
                lambda d: bench_server_against(
                    work, d, rounds, 200 if quick else 300, source_tree(args.baseline, work)
                ),
            ),
        ]
        assert tuple(name for name, _ in sections_run) == SECTIONS
        unknown = set(args.only or []) - set(SECTIONS)
        if unknown:
            parser.error(f"no section {', '.join(sorted(unknown))}")
        for i, (name, run) in enumerate(sections_run):
            if args.only and name not in args.only:
                continue
            if name == "baseline" and not args.baseline:
                continue
            # a ROS domain of its own (two for signed's side-by-side servers): what a failed
            # section left behind cannot meet the next one's agents
            try:
                result = run(domains[2 * i % len(domains)])
            except Exception as e:  # a section that fails is named, the run goes on
                failed[name] = f"{type(e).__name__}: {e}"
                print(f"section {name} FAILED: {failed[name]}", file=sys.stderr, flush=True)
                traceback.print_exc()
                continue
            if name == "speech_loop":
                report.setdefault("speech", {})["loop"] = result
            else:
                report[name] = result
            for key, r in result.get("ratios", {}).items():
                report["ratios"][
                    key if name in ("latency", "signed", "baseline") else f"{name}_{key}"
                ] = r
            for key, r in result.get("under_load", {}).get("ratios", {}).items():
                report["ratios"][f"{name}_loaded_{key}"] = r
            save(report, out)  # what is measured survives a run cut short
    save(report, out)
    print(table(report))
    print(f"\nreport: {args.out}")
    if failed:
        print(f"failed sections: {', '.join(failed)}", file=sys.stderr)
    return 1 if failed else 0


if __name__ == "__main__":
    code = main()
    if dds_deadlock.any_abandoned():  # the interpreter's exit would wait on it for ever
        exit_now(code)
    sys.exit(code)
