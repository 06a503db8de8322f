"""Transactions per second with 1, 4 and 8 subscribed agents, single operations and batches, next
to a raw rclpy relay."""

from __future__ import annotations

import json
import subprocess
import sys
import time
from pathlib import Path
from typing import Any

from harness import HERE, Procs, _wait_ready, session_with_agent
from std_msgs.msg import String

from dsr_graph.ros.qos import qos_stream
from dsr_graph.ros.session import RosSession


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


def _dsr_with_counters(procs, work: Path, domain: int, tag: str, k: int, expected: int):
    """A server, a writer and ``k`` subscribed counters waiting for ``expected`` deltas, the
    node the benchmark changes inserted: (the writer's session, the writer, the counters)."""
    procs.server(work / f"tp{tag}_state")
    ros, writer = session_with_agent(domain, "bench_writer")
    counters = [
        procs.start(f"counter{tag}_{i}", [sys.executable, str(HERE / "counter.py"), str(expected)])
        for i in range(k)
    ]
    for c in counters:
        _wait_ready(c)
    ok = []
    writer.send({"ops": [{"op": "insert_node", "name": "bench", "type": "transform"}]}, ok.append)
    ros.spin_until(lambda: ok, 10, "set-up")
    return ros, writer, counters


def bench_throughput(
    work: Path, domain: int, n: int, batch: int, agents_list: list[int]
) -> dict[str, Any]:
    results: dict[str, Any] = {}
    for k in agents_list:
        procs = Procs(work, domain)
        try:
            ros, writer, counters = _dsr_with_counters(procs, work, domain, f"{k}", k, n + 1)
            window, answered, t0 = 1000, [0], time.time()
            for i in range(n):  # flow control: at most `window` transactions unanswered
                while i - answered[0] >= window:
                    ros.executor.spin_once(timeout_sec=0.01)
                writer.send(
                    {"ops": [{"op": "set_node_attrs", "node": "bench", "attrs": {"level": i}}]},
                    lambda r, answered=answered: answered.__setitem__(0, answered[0] + 1),
                )
            single_result = _counters_result(counters, t0, n + 1)
            single = single_result["rate"]
            ros.close()
        finally:
            procs.stop_all()

        # batches of `batch` ops per transaction: operations per second
        procs = Procs(work, domain)
        try:
            m = max(1, n // batch)
            ros, writer, counters = _dsr_with_counters(procs, work, domain, f"b{k}", k, m + 1)
            t0 = time.time()
            for i in range(m):
                writer.send(
                    {
                        "ops": [
                            {
                                "op": "set_node_attrs",
                                "node": "bench",
                                "attrs": {"level": i * batch + j},
                            }
                            for j in range(batch)
                        ]
                    }
                )
            batched_ops = _counters_result(counters, t0, m + 1)["rate"] * batch
            ros.close()
        finally:
            procs.stop_all()

        # baseline: raw Strings of the same payload through a relay to k raw subscribers
        procs = Procs(work, domain)
        try:
            procs.start("relay", [sys.executable, str(HERE / "relay.py"), "bench/in", "bench/out"])
            counters = [
                procs.start(
                    f"raw{k}_{i}",
                    [sys.executable, str(HERE / "counter.py"), str(n), "--raw", "bench/out"],
                )
                for i in range(k)
            ]
            for c in counters:
                _wait_ready(c)
            ros = RosSession(name="bench_raw", domain_id=domain)
            pub = ros.node.create_publisher(String, "bench/in", qos_stream())
            ros.spin_until(
                lambda pub=pub, ros=ros, k=k: (
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
            raw_result = _counters_result(counters, t0, n)
            raw = raw_result["rate"]
            ros.close()
        finally:
            procs.stop_all()
        results[str(k)] = {
            "dsr_tx_per_s": single,
            "dsr_delivered": single_result["delivered"],
            "dsr_resyncs": single_result["resyncs"],
            "dsr_batched_ops_per_s": batched_ops,
            "batch": batch,
            "raw_msgs_per_s": raw,
            "raw_delivered": raw_result["delivered"],
            "ratio": single / raw,
        }
    eight = results.get("8")
    return {
        "agents": results,
        "targets": ">= 2000 single-op transactions/s with 8 agents",
        "met": bool(eight and eight["dsr_tx_per_s"] >= 2000),
    }
