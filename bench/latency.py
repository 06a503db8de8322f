"""Change-to-visible latency over two hops: a symbolic change (durable before it is broadcast) and a
volatile one, next to a raw rclpy relay and the fdatasync of a journal line on this disk; where the
time of one change goes."""

from __future__ import annotations

import json
import os
import sys
import time
from pathlib import Path
from typing import Any

from harness import (
    HERE,
    Procs,
    latency_samples,
    median_ms,
    percentiles,
    session_with_agent,
    timed_reader,
)
from std_msgs.msg import String

from dsr_graph.ros.qos import qos_stream


# ---------------------------------------------------------------------------- 1. latency
def bench_latency(work: Path, domain: int, n: int) -> dict[str, Any]:
    procs = Procs(work, domain)
    try:
        procs.server(work / "lat_state")
        ros, writer = session_with_agent(domain, "bench_writer")
        reader_node, reader, arrived = timed_reader(ros)
        done = []
        writer.send(
            {
                "ops": [
                    {"op": "insert_node", "name": "bench", "type": "transform"},
                    # a sensor's node: its frame_time is volatile (not journalled)
                    {"op": "insert_node", "name": "bench_sensor", "type": "person"},
                ]
            },
            done.append,
        )
        ros.spin_until(lambda: done, 10, "set-up")

        def change(i: int) -> dict[str, Any]:
            return {"ops": [{"op": "set_node_attrs", "node": "bench", "attrs": {"level": i}}]}

        def reading(i: int) -> dict[str, Any]:
            attrs = {"frame_time": float(i)}
            return {"ops": [{"op": "set_node_attrs", "node": "bench_sensor", "attrs": attrs}]}

        payload = json.dumps(dict(change(0), id=writer.next_id(), agent=writer.name))
        dsr = percentiles(latency_samples(ros, writer, arrived, n, change))
        volatile = percentiles(latency_samples(ros, writer, arrived, n, reading))
        # where the time goes: the same changes again, each step timed (a profile of one run)
        stages = {
            "symbolic": latency_stages(ros, writer, reader, arrived, n, change),
            "volatile": latency_stages(ros, writer, reader, arrived, n, reading),
        }
        procs.stop_all()
        fdatasync = percentiles(fdatasync_samples(work / "fdatasync_probe", payload, n))
        # as the server meets it: after a wait for the next request, not back to back
        fdatasync_paced = percentiles(
            fdatasync_samples(work / "fdatasync_probe", payload, n, pause=0.001)
        )

        # baseline: the same payload through a raw rclpy relay, same hops, same QoS
        procs.start("relay", [sys.executable, str(HERE / "relay.py"), "bench/in", "bench/out"])
        pub = ros.node.create_publisher(String, "bench/in", qos_stream())
        got: list[float] = []
        reader_node.create_subscription(
            String, "bench/out", lambda m: got.append(time.perf_counter()), qos_stream()
        )
        ros.spin_until(
            lambda: (
                pub.get_subscription_count() > 0 and reader_node.count_publishers("bench/out") > 0
            ),
            30,
            "the relay",
        )
        ros.spin_for(0.5)
        samples, publish = [], []
        for _ in range(n):
            before = len(got)
            sent = time.perf_counter()
            pub.publish(String(data=payload))
            publish.append(time.perf_counter() - sent)
            ros.spin_until(lambda before=before: len(got) > before, 10, "the relayed message")
            samples.append(got[-1] - sent)
        raw = percentiles(samples[n // 10 :])
        stages["raw"] = {
            "publish_ms": median_ms(publish[n // 10 :]),
            "relay_and_wire_ms": median_ms(
                [t - p for t, p in zip(samples[n // 10 :], publish[n // 10 :], strict=True)]
            ),
        }
        ros.close()
    finally:
        procs.stop_all()
    floor = raw["p50_ms"] + fdatasync["p50_ms"]  # a relay that also writes to the disk
    return {
        "dsr": dsr,
        "volatile": volatile,
        "raw": raw,
        "fdatasync": fdatasync,
        "fdatasync_paced": fdatasync_paced,
        "stages": stages,
        "payload_bytes": len(payload),
        "ratio_p50": dsr["p50_ms"] / raw["p50_ms"],
        "ratio_p99": dsr["p99_ms"] / raw["p99_ms"],
        "ratio_p50_durable_floor": dsr["p50_ms"] / floor,
        "ratio_p50_volatile": volatile["p50_ms"] / raw["p50_ms"],
        "targets": "symbolic p50 <= 1.5x (raw + fdatasync), p99 <= 2x raw; "
        "volatile p50 <= 1.25x raw",
        "met": dsr["p50_ms"] <= 1.5 * floor
        and dsr["p99_ms"] <= 2 * raw["p99_ms"]
        and volatile["p50_ms"] <= 1.25 * raw["p50_ms"],
    }


def fdatasync_samples(path: Path, payload: str, n: int, pause: float = 0.0) -> list[float]:
    """Seconds to append ``payload`` as a line and fdatasync it, as the journal does, n times
    (on the bench's own disk, in this run), back to back or ``pause`` s apart."""
    samples = []
    line = (payload + "\n").encode()
    with open(path, "ab") as f:
        for _ in range(n):
            if pause:
                time.sleep(pause)
            t = time.perf_counter()
            f.write(line)
            f.flush()
            os.fdatasync(f.fileno())
            samples.append(time.perf_counter() - t)
    path.unlink()
    return samples[n // 10 :]


def latency_stages(ros, writer, reader, arrived, n: int, change) -> dict[str, float]:
    """Medians (ms) of each step of a change, n changes: the writer's send (encode, publish);
    from its end to the first delta callback in this process (both hops and the server); the
    writer's replica's callback and the reader's (parse, apply, listeners); from the writer's
    callback's end to the reader's start (the executor's turn: both replicas share this
    process's executor, as the latency figures have them); send to the reader's replica."""
    calls: dict[str, list[tuple[float, float]]] = {"writer": [], "reader": []}
    plain = {"writer": writer._delta_sub.callback, "reader": reader._delta_sub.callback}

    def timed(agent, who: str) -> None:
        def callback(msg) -> None:
            start = time.perf_counter()
            plain[who](msg)
            calls[who].append((start, time.perf_counter()))

        agent._delta_sub.callback = callback

    timed(writer, "writer")
    timed(reader, "reader")
    try:
        rows = _stage_rows(ros, writer, arrived, n, change, calls)
    finally:  # the agents' own callbacks back
        writer._delta_sub.callback, reader._delta_sub.callback = plain["writer"], plain["reader"]
    rows = rows[n // 10 :]
    return {key: median_ms([r[key] for r in rows]) for key in rows[0]}


def _stage_rows(ros, writer, arrived, n: int, change, calls) -> list[dict[str, float]]:
    rows = []
    for i in range(n):
        for kept in calls.values():
            kept.clear()
        sent = time.perf_counter()
        ident = writer.send(change(10**6 + i))
        published = time.perf_counter()
        while ident not in arrived or not calls["writer"]:  # as latency_samples waits
            ros.executor.spin_once(timeout_sec=0.0005)
            if time.perf_counter() - sent > 10:
                raise RuntimeError("a change was not seen within 10 s")
        (w_start, w_end), (r_start, r_end) = calls["writer"][-1], calls["reader"][-1]
        rows.append(
            {
                "send_ms": published - sent,
                "server_and_wire_ms": min(w_start, r_start) - published,
                "writer_replica_ms": w_end - w_start,
                "between_ms": r_start - w_end,
                "reader_replica_ms": r_end - r_start,
                "total_ms": arrived[ident] - sent,
            }
        )
    return rows
