"""What signing the DSR's traffic costs: latency in interleaved rounds, throughput with one agent
and a Barthel run's CPU, with DSR_SECURITY=enforce next to off."""

from __future__ import annotations

import contextlib
from pathlib import Path
from typing import Any

from barthel import bench_barthel
from harness import security
from latency import latency_rig
from rounds import interleave, pooled, ratio
from throughput import bench_throughput

MODES = ("off", "enforce")


def bench_signed(
    work: Path, domain: int, rounds: int, per_round: int, tx: int, scale: float
) -> dict[str, Any]:
    """The change-to-visible latency with the DSR's traffic signed and checked (enforce) and
    without (off): two servers side by side (``domain`` and the next), sampled in interleaved
    rounds; then throughput (one agent) and a Barthel run in each mode, one after the other."""
    from dsr_graph.formats.keystore import Keystore

    keystore, _ = Keystore.init(work / "bench_keystore")
    for name in (
        "/bench_writer",
        "/bench_reader",
        *(f"/bench_{who}_{m}" for who in ("writer", "reader") for m in MODES),
    ):
        keystore.add(name)
    with contextlib.ExitStack() as stack:
        rigs = {}
        for i, mode in enumerate(MODES):
            with security(mode, keystore.root):  # each side's processes and agents keep it
                rigs[mode] = stack.enter_context(latency_rig(work, domain + i, tag=f"_{mode}"))
        latency = interleave(
            {mode: (lambda r, rig=rig: rig.symbolic(per_round)) for mode, rig in rigs.items()},
            rounds,
        )
    results: dict[str, Any] = {}
    for mode in MODES:
        with security(mode, keystore.root):
            throughput = bench_throughput(work, domain, 3, tx, 100, [1])["agents"]["1"]
        barthel = bench_barthel(work, scale, security=mode)
        results[mode] = {
            "latency": pooled(latency[mode]),
            "tx_per_s": throughput["dsr_tx_per_s"],
            "raw_msgs_per_s": throughput["raw_msgs_per_s"],
            "barthel_cpu_s": barthel["cpu_total_s"],
            "barthel_server_cpu_s": barthel["cpu_s"].get("dsr_server"),
            "barthel_completed": barthel["completed"],
        }
    off, on = results["off"], results["enforce"]
    results["ratios"] = {
        "enforce_vs_off_p50": ratio(latency["enforce"], latency["off"], "p50_ms"),
        "enforce_vs_off_p99": ratio(latency["enforce"], latency["off"], "p99_ms"),
    }
    results["cost"] = {
        "p50_ms": on["latency"]["p50_ms"] - off["latency"]["p50_ms"],
        "p99_ms": on["latency"]["p99_ms"] - off["latency"]["p99_ms"],
        "throughput_ratio": on["tx_per_s"] / off["tx_per_s"],
        "barthel_cpu_ratio": on["barthel_cpu_s"] / max(off["barthel_cpu_s"], 1e-9),
    }
    return results
