"""The DSR benchmarks, each figure next to a plain-rclpy (or naive numpy) baseline measured in the
same run. Run through scripts/bench.sh; writes a JSON report and prints a table.

Sections: latency (change-to-visible over two hops: a symbolic change, durable before it is
broadcast, and a volatile one, next to a raw rclpy relay and the fdatasync of a journal line on
this disk), throughput (1/4/8 subscribed agents, single ops and batches), scale (1k/10k/100k
nodes: cost per op, snapshot to a late joiner, memory), kinematics (transform queries on trees
of depth 2/10/50, cold and cached), barthel (a fast test: wall time and CPU seconds per
process), gug (a patient's skeleton streamed through the DSR at 30 Hz, 14 joints, as Person
writes it: the server's CPU, frames written of those offered, a Speech-sized change's latency
and the journal's growth, each against the same without the stream, quiet and with every core
kept busy; a whole Get Up & Go run's CPU against the Barthel run's; in a full run, every shipped
GUG scenario through launch.sh, quiet and loaded), camera (640x480 colour and depth images at
30 Hz beside the skeleton: the server's CPU, images offered, written and delivered whole to
another process's replica, a Speech change's latency against the quiet figure, and what one hop
costs a frame as base64 JSON or as blobs), signed (what signing the DSR's traffic
costs: latency, throughput with one agent and the Barthel run's CPU, with DSR_SECURITY=enforce
next to off), gc (a snapshot encoded and loaded with the DSR processes' collector policy next to
CPython's default thresholds, in interleaved rounds).

Each section is a module of its own beside this one.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

from barthel import bench_barthel
from camera import bench_camera
from gug import bench_gug
from harness import ROOT
from kinematics import bench_kinematics
from latency import bench_latency
from scale import bench_scale, build_world
from signed import bench_signed
from tables import table
from throughput import bench_throughput


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument(
        "--quick",
        action="store_true",
        help="about 4 minutes: fewer samples, sizes up to 10k, 1 and 8 agents, a Barthel run "
        "at pace x0.05, no Get Up & Go scenarios",
    )
    parser.add_argument("--out", default=str(ROOT / "bench-results" / "bench.json"))
    parser.add_argument("--only", nargs="*", help="sections to run (default all)")
    args = parser.parse_args()
    quick = args.quick
    sections = set(
        args.only
        or [
            "latency",
            "throughput",
            "scale",
            "kinematics",
            "barthel",
            "gug",
            "camera",
            "signed",
            "speech",
            "speech_loop",
            "provenance",
            "rt_history",
            "gc",
        ]
    )
    domain = 10 + os.getpid() % 90
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
    }
    with tempfile.TemporaryDirectory() as tmp:
        work = Path(tmp)
        if "kinematics" in sections:
            report["kinematics"] = bench_kinematics([2, 10, 50], 2000 if quick else 20000)
        if "latency" in sections:
            report["latency"] = bench_latency(work, domain, 200 if quick else 2000)
        if "throughput" in sections:
            report["throughput"] = bench_throughput(
                work, domain, 1000 if quick else 5000, 100, [1, 8] if quick else [1, 4, 8]
            )
        if "scale" in sections:
            report["scale"] = bench_scale(
                work,
                domain,
                [1000, 10000] if quick else [1000, 10000, 100000],
                2000 if quick else 10000,
            )
        if "barthel" in sections:
            report["barthel"] = bench_barthel(work, 0.05 if quick else 0.1)
        if "gug" in sections:
            report["gug"] = bench_gug(
                work, domain, 5.0 if quick else 20.0, 100 if quick else 500, 0.1, not quick
            )
        if "camera" in sections:
            report["camera"] = bench_camera(
                work, domain, 5.0 if quick else 20.0, 100 if quick else 500
            )
        if "provenance" in sections:
            from cortex import bench_provenance

            report["provenance"] = bench_provenance(
                build_world, [10000] if quick else [10000, 100000], 2000 if quick else 10000
            )
        if "rt_history" in sections:
            from cortex import bench_rt_history

            report["rt_history"] = bench_rt_history([2, 10, 50], 2000 if quick else 20000)
        if "gc" in sections:
            from gc_policy import bench_gc_policy

            report["gc"] = bench_gc_policy(10000 if quick else 100000, 5 if quick else 10)
        if "speech" in sections:
            from speech import bench_speech

            report["speech"] = bench_speech(quick)
        if "speech_loop" in sections:
            from speech import bench_speech_loop

            report.setdefault("speech", {})["loop"] = bench_speech_loop(work, domain, ROOT)
        if "signed" in sections:
            report["signed"] = bench_signed(
                work, domain, 200 if quick else 2000, 1000 if quick else 5000, 0.1
            )
    Path(args.out).parent.mkdir(parents=True, exist_ok=True)
    Path(args.out).write_text(json.dumps(report, indent=2))
    print(table(report))
    print(f"\nreport: {args.out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
