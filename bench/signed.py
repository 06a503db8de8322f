"""What signing the DSR's traffic costs: latency, throughput with one agent and a Barthel run's CPU,
with DSR_SECURITY=enforce next to off."""

from __future__ import annotations

from pathlib import Path
from typing import Any

from barthel import bench_barthel
from harness import security
from latency import bench_latency
from throughput import bench_throughput


def bench_signed(work: Path, domain: int, n: int, tx: int, scale: float) -> dict[str, Any]:
    """The same latency, throughput (one agent) and Barthel run with the DSR's traffic signed
    and checked (enforce) and without (off), one after the other in this run."""
    from dsr_graph.formats.keystore import Keystore

    keystore, _ = Keystore.init(work / "bench_keystore")
    for name in ("/bench_writer", "/bench_reader"):
        keystore.add(name)
    results: dict[str, Any] = {}
    for mode in ("off", "enforce"):
        with security(mode, keystore.root):
            latency = bench_latency(work, domain, n)
            throughput = bench_throughput(work, domain, tx, 100, [1])["agents"]["1"]
        barthel = bench_barthel(work, scale, security=mode)
        results[mode] = {
            "latency": latency["dsr"],
            "raw_latency": latency["raw"],
            "tx_per_s": throughput["dsr_tx_per_s"],
            "raw_msgs_per_s": throughput["raw_msgs_per_s"],
            "barthel_cpu_s": barthel["cpu_total_s"],
            "barthel_server_cpu_s": barthel["cpu_s"].get("dsr_server"),
            "barthel_completed": barthel["completed"],
        }
    off, on = results["off"], results["enforce"]
    results["cost"] = {
        "p50_ms": on["latency"]["p50_ms"] - off["latency"]["p50_ms"],
        "p99_ms": on["latency"]["p99_ms"] - off["latency"]["p99_ms"],
        "throughput_ratio": on["tx_per_s"] / off["tx_per_s"],
        "barthel_cpu_ratio": on["barthel_cpu_s"] / max(off["barthel_cpu_s"], 1e-9),
    }
    return results
