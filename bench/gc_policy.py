"""The garbage-collector policy of a DSR process (ros/process_gc.py) against CPython's default
thresholds, on the bulk work it is for: a server encoding a snapshot of the scale world column by
column, and a replica parsing and loading it with every node and edge built. Interleaved rounds
in one process (default, policy, default, policy ...), each figure the median over the rounds of
that side with its range, and the median of the per-round ratios."""

from __future__ import annotations

import gc
import statistics
import time
from typing import Any

from scale import build_world

from dsr_graph.formats import dsr_json
from dsr_graph.formats.safe_json import loads_object
from dsr_graph.protocol.replica import Replica
from dsr_graph.protocol.server_core import ServerCore
from dsr_graph.protocol.snapshot_text import snapshot_text
from dsr_graph.ros.process_gc import THRESHOLDS

DEFAULT = (700, 10, 10)  # CPython's


def _encode_and_load(core: ServerCore) -> tuple[float, float]:
    start = time.perf_counter()
    text, _ = snapshot_text(core, dsr_json.COLUMNS, known=lambda data: None)
    encoded = time.perf_counter()
    replica = Replica(core.graph.vocabulary)
    replica.load_snapshot(loads_object(text, None, walk=False))
    sum(1 for _ in replica.graph.nodes())  # every node built
    replica.graph.edge_count()  # and every edge
    loaded = time.perf_counter()
    del replica, text
    gc.collect()  # the next round starts from the same heap
    return encoded - start, loaded - encoded


def bench_gc_policy(nodes: int, rounds: int) -> dict[str, Any]:
    core = ServerCore(build_world(nodes))
    before = gc.get_threshold()
    runs: dict[str, list[tuple[float, float]]] = {"default": [], "policy": []}
    try:
        for _ in range(rounds):
            for side, thresholds in (("default", DEFAULT), ("policy", THRESHOLDS)):
                gc.set_threshold(*thresholds)
                runs[side].append(_encode_and_load(core))
    finally:
        gc.set_threshold(*before)
    out: dict[str, Any] = {"nodes": nodes, "rounds": rounds, "policy_thresholds": THRESHOLDS}
    for k, step in enumerate(("encode", "load")):
        for side, samples in runs.items():
            values = [s[k] for s in samples]
            out[f"{step}_{side}_s"] = {
                "median": statistics.median(values),
                "min": min(values),
                "max": max(values),
            }
        ratios = [p[k] / d[k] for d, p in zip(runs["default"], runs["policy"], strict=True)]
        out[f"{step}_ratio"] = {
            "median": statistics.median(ratios),
            "min": min(ratios),
            "max": max(ratios),
        }
    return out


def table(gcp: dict[str, Any]) -> list[str]:
    lines = [
        f"gc policy    {gcp['nodes']} nodes, {gcp['rounds']} interleaved rounds: median s (range)"
    ]
    for step in ("encode", "load"):
        d, p, r = gcp[f"{step}_default_s"], gcp[f"{step}_policy_s"], gcp[f"{step}_ratio"]
        lines.append(
            f"  {step:<7} default {d['median']:.3f} ({d['min']:.3f}-{d['max']:.3f})  policy "
            f"{p['median']:.3f} ({p['min']:.3f}-{p['max']:.3f})  policy/default "
            f"{r['median']:.2f}x ({r['min']:.2f}-{r['max']:.2f})"
        )
    return lines
