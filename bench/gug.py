"""The skeleton stream's load on the DSR and a whole Get Up & Go run's CPU, quiet and with every
core busy; in a full run, every shipped GUG scenario through launch.sh."""

from __future__ import annotations

import os
from pathlib import Path
from typing import Any

from barthel import bench_barthel
from harness import ROOT, busy_cores
from streams import gug_stream


def gug_runs(work: Path, scale: float, tag: str) -> dict[str, Any]:
    """Every shipped Get Up & Go scenario of a patient who walks, through launch.sh: what each
    stored (gug_cannot_rise, a minute of trials that are void by design, is the tests')."""
    from clarc_sim.patient.scenario import load

    runs = {}
    for scenario in sorted((ROOT / "scenarios").glob("gug_*.yaml")):
        if not load(str(scenario)).rises:
            continue
        run = bench_barthel(work, scale, scenario, db=f"gug_{tag}_{scenario.stem}.sqlite")
        result = run["result"] or {}
        runs[scenario.stem] = {
            "completed": run["completed"],
            "wall_s": run["wall_s"],
            "cpu_total_s": run["cpu_total_s"],
            "outcome": result.get("outcome"),
            "tug_seconds": result.get("tug_seconds"),
            "trials": result.get("trials"),
            "void_reasons": result.get("void_reasons"),
        }
    return runs


def bench_gug(
    work: Path,
    domain: int,
    seconds: float,
    rounds: int,
    per_round: int,
    scale: float,
    scenarios: bool,
) -> dict[str, Any]:
    """The skeleton stream's load on the DSR and a whole GUG run's CPU, quiet; and the same
    with every core kept busy by another process (``under_load``): frames written of those
    offered, a Speech change's latency, and (``scenarios``) what each shipped GUG scenario
    stored, quiet and loaded."""
    out = gug_stream(work, domain, seconds, rounds, per_round)
    out["robot"] = bench_barthel(work, scale, ROOT / "scenarios" / "gug_normal.yaml", db="gug.db")
    cores = os.cpu_count() or 2
    with busy_cores(cores):
        loaded = gug_stream(work, domain, seconds, rounds, per_round)
    out["under_load"] = {"busy_processes": cores} | {
        k: loaded[k]
        for k in (
            "server_cpu_streaming",
            "frames_written_per_s",
            "frames_offered_per_s",
            "frames_per_tx",
            "latency_quiet",
            "latency_streaming",
            "ratios",
        )
    }
    if scenarios:
        out["scenarios"] = {"pace": scale, "quiet": gug_runs(work, scale, "quiet")}
        with busy_cores(cores):
            out["scenarios"]["loaded"] = gug_runs(work, scale, "loaded")
    return out
