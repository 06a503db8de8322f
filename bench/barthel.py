"""A whole Barthel run through launch.sh: wall time and CPU seconds per process."""

from __future__ import annotations

import json
import os
import re
import subprocess
import time
from pathlib import Path
from typing import Any

from harness import ROOT


# ---------------------------------------------------------------------------- 5. the Barthel run
def bench_barthel(
    work: Path,
    scale: float,
    scenario: Path | None = None,
    security: str = "enforce",
    db: str = "bench.sqlite",
) -> dict[str, Any]:
    """A whole run through launch.sh (the Barthel default, or ``scenario``): wall and CPU, and
    the result it stored (the newest in the results store ``db``)."""
    report = work / "cpu.txt"
    report.unlink(missing_ok=True)
    env = dict(os.environ, CLARC_CPU_REPORT=str(report))
    t = time.perf_counter()
    run = subprocess.run(
        [
            str(ROOT / "scripts" / "launch.sh"),
            *(["--scenario", str(scenario)] if scenario else []),
            "--db",
            str(work / db),
            "--scale",
            str(scale),
            "--run-dir",  # a fresh DSR each run (a run directory reused resumes its graph)
            str(work / f"run_{Path(db).stem}_{security}"),
            "--viewer-port",
            "0",
            "--dashboard-port",
            "0",
            "--security",
            security,
        ],
        capture_output=True,
        text=True,
        env=env,
        timeout=600,
    )
    wall = time.perf_counter() - t
    cpu = {}
    if report.exists():
        for line in report.read_text().splitlines():
            name, seconds = line.split()
            cpu[name] = float(seconds)
    test_s = None
    for line in run.stdout.splitlines():  # the monitor's "[  12.3s] ..." lines
        stamp = re.match(r"\[\s*(\d+\.\d+)s\]", line)
        if stamp:
            test_s = float(stamp.group(1))
    stored = subprocess.run(
        ["clarc", "results", "--db", str(work / db), "--json"],
        capture_output=True,
        text=True,
        timeout=60,
    )
    results = json.loads(stored.stdout) if stored.returncode == 0 else []
    return {
        "completed": run.returncode == 0,
        "result": results[-1] if results else None,
        "security": security,
        "pace": scale,
        "wall_s": wall,
        "test_s": test_s,
        "cpu_s": cpu,
        "cpu_total_s": sum(cpu.values()),
    }
