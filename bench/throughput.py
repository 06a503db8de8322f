"""Transactions per second with 1, 4 and 8 subscribed agents, single operations and batches, next
to a raw rclpy relay: the DSR and the relay side by side, their bursts interleaved in rounds."""

from __future__ import annotations

import json
import statistics
import sys
import time
from pathlib import Path
from typing import Any

from harness import HERE, Procs, _wait_ready, agent_session
from rounds import interleave, summary
from std_msgs.msg import String

from dsr_graph.ros.qos import qos_stream

WINDOW = 1000  # transactions a writer leaves unanswered at most (flow control)


class Counters:
    """Subscribed processes counting in bursts (counter.py)."""

    def __init__(self, procs: Procs, tag: str, k: int, raw_topic: str = ""):
        argv = [sys.executable, str(HERE / "counter.py")] + (
            ["--raw", raw_topic] if raw_topic else []
        )
        self.procs = [procs.start(f"{tag}_{i}", argv, stdin=True) for i in range(k)]
        for c in self.procs:
            _wait_ready(c)

    def burst(self, expected: int, send) -> dict[str, float]:
        """Arm every counter for ``expected`` arrivals, ``send()``, and the rate (per second)
        that reached every counter, the share that arrived and the resynchronisations."""
        for c in self.procs:
            c.stdin.write(f"{expected}\n")
            c.stdin.flush()
        for c in self.procs:
            _wait_ready(c, word="armed")
        t0 = time.time()
        send()
        seen = [json.loads(c.stdout.readline()) for c in self.procs]
        least = min(s["count"] for s in seen)
        last = max(s["last"] or t0 for s in seen)
        return {
            "rate": least / max(last - t0, 1e-9),
            "delivered": least / expected,
            "resyncs": sum(s["resyncs"] for s in seen),
        }


def bench_throughput(
    work: Path, domain: int, rounds: int, n: int, batch: int, agents_list: list[int]
) -> dict[str, Any]:
    """For each number of subscribed agents: ``rounds`` interleaved rounds of ``n`` single-op
    transactions through the DSR and ``n`` messages of the same payload through the relay; then
    batches of ``batch`` ops (operations per second)."""
    results: dict[str, Any] = {}
    for k in agents_list:
        with Procs(work, domain) as procs:
            procs.server(work / f"tp{k}_state")
            procs.start(
                f"relay{k}", [sys.executable, str(HERE / "relay.py"), "bench/in", "bench/out"]
            )
            with agent_session(domain, "bench_writer") as (ros, writer):
                results[str(k)] = _with_agents(procs, ros, writer, k, rounds, n, batch)
    eight = results.get("8")
    return {
        "agents": results,
        "rounds": {"count": rounds, "transactions_per_round": n},
        "ratios": {f"dsr_vs_raw_tx_{k}_agents": v.pop("ratio_rounds") for k, v in results.items()},
        "targets": ">= 2000 single-op transactions/s with 8 agents",
        "met": bool(eight and eight["dsr_tx_per_s"] >= 2000),
    }


def _with_agents(procs, ros, writer, k: int, rounds: int, n: int, batch: int) -> dict[str, Any]:
    dsr = Counters(procs, f"counter{k}", k)
    raw = Counters(procs, f"raw{k}", k, "bench/out")
    ok: list = []
    writer.send({"ops": [{"op": "insert_node", "name": "bench", "type": "transform"}]}, ok.append)
    ros.spin_until(lambda: ok, 10, "set-up")
    pub = ros.node.create_publisher(String, "bench/in", qos_stream())
    ros.spin_until(
        lambda: pub.get_subscription_count() > 0 and ros.node.count_subscribers("bench/out") >= k,
        30,
        "the relay and its subscribers",
    )
    payload = json.dumps(
        {
            "ops": [{"op": "set_node_attrs", "node": "bench", "attrs": {"level": 0}}],
            "id": "/bench_writer:000000:1",
            "agent": "/bench_writer",
        }
    )
    sent = [0]  # every change sets a value not set before

    def single_ops() -> None:
        answered = [0]
        first = sent[0]
        for i in range(n):
            while i - answered[0] >= WINDOW:
                ros.executor.spin_once(timeout_sec=0.01)
            writer.send(
                {"ops": [{"op": "set_node_attrs", "node": "bench", "attrs": {"level": first + i}}]},
                lambda r: answered.__setitem__(0, answered[0] + 1),
            )
        sent[0] += n

    def relayed() -> None:
        for i in range(n):
            pub.publish(String(data=payload))
            if i % 500 == 499:
                ros.spin_for(0.001)

    runs = interleave(
        {"dsr": lambda r: [dsr.burst(n, single_ops)], "raw": lambda r: [raw.burst(n, relayed)]},
        rounds,
    )
    m = max(1, n // batch)

    def batches() -> None:
        for _ in range(m):
            ops = [
                {"op": "set_node_attrs", "node": "bench", "attrs": {"level": sent[0] + j}}
                for j in range(batch)
            ]
            sent[0] += batch
            writer.send({"ops": ops})

    batched = dsr.burst(m, batches)
    dsr_rounds = [r[0] for r in runs["dsr"]]
    raw_rounds = [r[0] for r in runs["raw"]]
    rate = lambda rs: statistics.median(r["rate"] for r in rs)  # noqa: E731
    return {
        "dsr_tx_per_s": rate(dsr_rounds),
        "dsr_delivered": min(r["delivered"] for r in dsr_rounds),
        "dsr_resyncs": sum(r["resyncs"] for r in dsr_rounds),
        "dsr_batched_ops_per_s": batched["rate"] * batch,
        "batch": batch,
        "raw_msgs_per_s": rate(raw_rounds),
        "raw_delivered": min(r["delivered"] for r in raw_rounds),
        "ratio": rate(dsr_rounds) / rate(raw_rounds),
        "ratio_rounds": summary(
            [d["rate"] / w["rate"] for d, w in zip(dsr_rounds, raw_rounds, strict=True)]
        ),
    }
