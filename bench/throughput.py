"""Transactions per second with 1, 4 and 8 subscribed agents, single operations and batches, next
to a raw rclpy relay: a DSR run and a relay run, each with processes of its own, alternating in
rounds (rounds.py)."""

from __future__ import annotations

import json
import statistics
import subprocess
import sys
import time
from pathlib import Path
from typing import Any

from harness import HERE, Procs, _wait_ready, agent_session
from rounds import interleave, summary
from std_msgs.msg import String

from dsr_graph.ros.qos import qos_stream
from dsr_graph.ros.session import RosSession

WINDOW = 1000  # transactions a writer leaves unanswered at most (flow control)


def _counters_result(
    counters: list[subprocess.Popen], t0: float, expected: int
) -> dict[str, float]:
    """Messages (or deltas applied) per second that reached every counter, the share that
    arrived, and how many resynchronisations the replicas needed."""
    last, least, resyncs = 0.0, None, 0
    for c in counters:
        out = c.stdout.read()  # after readline(): communicate() would miss what it buffered
        c.wait(timeout=300)
        seen = json.loads(out.strip().splitlines()[-1])
        last = max(last, seen["last"] or t0)
        least = seen["count"] if least is None else min(least, seen["count"])
        resyncs += seen.get("resyncs", 0)
    return {
        "rate": (least or 0) / max(last - t0, 1e-9),
        "delivered": (least or 0) / expected,
        "resyncs": resyncs,
    }


def _counters(procs: Procs, tag: str, k: int, expected: int, raw: bool = False):
    argv = [sys.executable, str(HERE / "counter.py"), str(expected)]
    counters = [
        procs.start(f"{tag}_{i}", argv + (["--raw", "bench/out"] if raw else [])) for i in range(k)
    ]
    for c in counters:
        _wait_ready(c)
    return counters


def dsr_run(work: Path, domain: int, tag: str, k: int, n: int, batch: int = 1) -> dict[str, float]:
    """A server, a writer and ``k`` subscribed counters of their own: ``n`` transactions of
    ``batch`` set-attribute ops each, at most WINDOW unanswered (single ops) or all at once."""
    with Procs(work, domain) as procs:
        procs.server(work / f"tp{tag}_state")
        with agent_session(domain, "bench_writer") as (ros, writer):
            counters = _counters(procs, f"counter{tag}", k, n + 1)
            ok: list = []
            writer.send(
                {"ops": [{"op": "insert_node", "name": "bench", "type": "transform"}]}, ok.append
            )
            ros.spin_until(lambda: ok, 10, "set-up")
            ros.spin_for(1.0)  # as the relay's run: discovery's first announcements are over
            answered, t0 = [0], time.time()
            for i in range(n):
                while batch == 1 and i - answered[0] >= WINDOW:
                    ros.executor.spin_once(timeout_sec=0.01)
                ops = [
                    {"op": "set_node_attrs", "node": "bench", "attrs": {"level": i * batch + j}}
                    for j in range(batch)
                ]
                writer.send({"ops": ops}, lambda r: answered.__setitem__(0, answered[0] + 1))
            return _counters_result(counters, t0, n + 1)


def raw_run(work: Path, domain: int, tag: str, k: int, n: int) -> dict[str, float]:
    """The same payload as ``n`` raw Strings through a relay to ``k`` raw subscribers."""
    with Procs(work, domain) as procs:
        procs.start(
            f"relay{tag}", [sys.executable, str(HERE / "relay.py"), "bench/in", "bench/out"]
        )
        counters = _counters(procs, f"raw{tag}", k, n, raw=True)
        ros = RosSession(name="bench_raw", domain_id=domain)
        try:
            pub = ros.node.create_publisher(String, "bench/in", qos_stream())
            ros.spin_until(
                lambda: (
                    pub.get_subscription_count() > 0
                    and ros.node.count_subscribers("bench/out") >= k
                ),
                30,
                "the relay and subscribers",
            )
            ros.spin_for(1.0)
            payload = json.dumps(
                {
                    "ops": [{"op": "set_node_attrs", "node": "bench", "attrs": {"level": 0}}],
                    "id": "/bench_writer:000000:1",
                    "agent": "/bench_writer",
                }
            )
            t0 = time.time()
            for i in range(n):
                pub.publish(String(data=payload))
                if i % 500 == 499:
                    ros.spin_for(0.001)
            return _counters_result(counters, t0, n)
        finally:
            ros.close()


def bench_throughput(
    work: Path, domain: int, rounds: int, n: int, batch: int, agents_list: list[int]
) -> dict[str, Any]:
    """For each number of subscribed agents: ``rounds`` rounds of a DSR run (``n`` single-op
    transactions) and a relay run (``n`` messages), alternating; then one DSR run of batches of
    ``batch`` ops (operations per second)."""
    results: dict[str, Any] = {}
    for k in agents_list:
        runs = interleave(
            {
                "dsr": lambda r, k=k: [dsr_run(work, domain, f"{k}_{r}", k, n)],
                "raw": lambda r, k=k: [raw_run(work, domain, f"{k}_{r}", k, n)],
            },
            rounds,
        )
        dsr, raw = [r[0] for r in runs["dsr"]], [r[0] for r in runs["raw"]]
        batched = dsr_run(work, domain, f"b{k}", k, max(1, n // batch), batch)
        rate = lambda rs: statistics.median(r["rate"] for r in rs)  # noqa: E731
        results[str(k)] = {
            "dsr_tx_per_s": rate(dsr),
            "dsr_delivered": min(r["delivered"] for r in dsr),
            "dsr_resyncs": sum(r["resyncs"] for r in dsr),
            "dsr_batched_ops_per_s": batched["rate"] * batch,
            "batch": batch,
            "raw_msgs_per_s": rate(raw),
            "raw_delivered": min(r["delivered"] for r in raw),
            "ratio": rate(dsr) / rate(raw),
            "ratio_rounds": summary([d["rate"] / w["rate"] for d, w in zip(dsr, raw, strict=True)]),
        }
    eight = results.get("8")
    ratios = {f"dsr_vs_raw_tx_{k}_agents": v.pop("ratio_rounds") for k, v in results.items()}
    eight_ratio = ratios.get("dsr_vs_raw_tx_8_agents", {}).get("median", 0.0)
    return {
        "agents": results,
        "rounds": {"count": rounds, "transactions_per_round": n},
        "ratios": ratios,
        "targets": ">= 2000 single-op transactions/s with 8 agents, and (issue 35) at least the "
        "relay's messages/s (the median of the rounds' ratios >= 1)",
        "met": bool(eight and eight["dsr_tx_per_s"] >= 2000 and eight_ratio >= 1.0),
    }
