"""A restarted agent: killed outright and respawned at once (as launch does), how long its
successor takes to be in sync and to have its first change accepted, next to the same agent's
first start. The predecessor stays listed in the ROS graph until its DDS lease runs out."""

from __future__ import annotations

import json
import os
import signal
import statistics
import sys
from pathlib import Path
from typing import Any

from harness import HERE, ROOT, Procs


def bench_restart(work: Path, domain: int, kills: int) -> dict[str, Any]:
    with Procs(work, domain) as procs:
        procs.server(work / f"restart_state_{domain}", str(ROOT / "worlds" / "clarc_room.json"))
        runs = []
        agent = None
        for i in range(kills + 1):
            if agent is not None:
                os.killpg(agent.pid, signal.SIGKILL)
                agent.wait(timeout=10)
            agent = procs.start(
                f"respawned_{i}", [sys.executable, str(HERE / "respawned.py"), "respawned"]
            )
            line = agent.stdout.readline()  # bounded by the agent's own waits
            if not line:
                raise RuntimeError(f"start {i} of the agent printed nothing (respawned_{i}.log)")
            runs.append(json.loads(line))
    successors = runs[1:]

    def spread(key: str) -> dict[str, float]:
        xs = [r[key] for r in successors]
        return {"median": statistics.median(xs), "min": min(xs), "max": max(xs)}

    return {
        "first_start": runs[0],
        "successors": successors,
        "ready_s": spread("ready_s"),
        "accepted_s": spread("accepted_s"),
        "all_accepted": all(r["accepted"] for r in runs),
    }


def table(r: dict[str, Any]) -> list[str]:
    first, ready, accepted = r["first_start"], r["ready_s"], r["accepted_s"]
    return [
        f"restart: an agent killed and respawned at once, {len(r['successors'])} times: in sync "
        f"after {ready['median']:.2f} s ({ready['min']:.2f}-{ready['max']:.2f}), first change "
        f"accepted after {accepted['median']:.2f} s ({accepted['min']:.2f}-{accepted['max']:.2f}); "
        f"its first start: {first['ready_s']:.2f} s and {first['accepted_s']:.2f} s"
        + ("" if r["all_accepted"] else "  [a change was refused]")
    ]
