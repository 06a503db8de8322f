"""The DSR benchmarks, each figure next to a plain-rclpy (or naive numpy) baseline measured in the
same run. Run through scripts/bench.sh; writes a JSON report and prints a table.

Sections: latency (change-to-visible over two hops: a symbolic change, durable before it is
broadcast, and a volatile one, next to a raw rclpy relay and the fdatasync of a journal line on
this disk), throughput (1/4/8 subscribed agents, single ops and batches), scale (1k/10k/100k
nodes: cost per op, snapshot to a late joiner, memory), kinematics (transform queries on trees
of depth 2/10/50, cold and cached), barthel (a fast test: wall time and CPU seconds per
process), gug (a patient's skeleton streamed through the DSR at 30 Hz, 14 joints, as Person
writes it: the server's CPU, frames written of those offered, a Speech-sized change's latency
and the journal's growth, each against the same without the stream, quiet and with every core
kept busy; a whole Get Up & Go run's CPU against the Barthel run's; in a full run, every shipped
GUG scenario through launch.sh, quiet and loaded), camera (640x480 colour and depth images at
30 Hz beside the skeleton: the server's CPU, images offered, written and delivered whole to
another process's replica, a Speech change's latency against the quiet figure, and what one hop
costs a frame as base64 JSON or as blobs), signed (what signing the DSR's traffic
costs: latency, throughput with one agent and the Barthel run's CPU, with DSR_SECURITY=enforce
next to off).
"""

from __future__ import annotations

import argparse
import contextlib
import gc
import json
import os
import platform
import random
import re
import shutil
import signal
import statistics
import subprocess
import sys
import tempfile
import time
import tracemalloc
from pathlib import Path
from typing import Any

import numpy as np
from std_msgs.msg import String

from dsr_graph.formats import dsr_json
from dsr_graph.model import rigid
from dsr_graph.model.graph import Graph
from dsr_graph.model.transaction import apply_ops
from dsr_graph.ros.agent import DsrAgent
from dsr_graph.ros.qos import qos_stream
from dsr_graph.ros.session import RosSession

ROOT = Path(__file__).resolve().parent.parent
HERE = Path(__file__).resolve().parent


# ---------------------------------------------------------------------------- processes
class Procs:
    def __init__(self, workdir: Path, domain: int):
        self.workdir, self.domain, self.procs = workdir, domain, []
        self.env = dict(
            os.environ,
            ROS_DOMAIN_ID=str(domain),
            ROS_AUTOMATIC_DISCOVERY_RANGE="LOCALHOST",
            PYTHONUNBUFFERED="1",
        )

    def start(self, name: str, argv: list[str]) -> subprocess.Popen:
        exe = shutil.which(argv[0]) or argv[0]
        p = subprocess.Popen(
            [exe, *argv[1:]],
            stdout=subprocess.PIPE,
            stderr=open(self.workdir / f"{name}.log", "w"),
            env=self.env,
            text=True,
            start_new_session=True,
        )
        self.procs.append(p)
        return p

    def server(self, state: Path, world: str = "") -> subprocess.Popen:
        args = [
            "dsr_server",
            "--ros-args",
            "-p",
            f"state_dir:={state}",
            "-p",
            "publish_poses:=false",
        ]
        if world:
            args += ["-p", f"world_file:={world}"]
        return self.start("server", args)

    def stop_all(self) -> None:
        for p in self.procs:
            if p.poll() is None:
                os.killpg(p.pid, signal.SIGINT)
        for p in self.procs:
            try:
                p.wait(timeout=10)
            except subprocess.TimeoutExpired:
                os.killpg(p.pid, signal.SIGKILL)
                p.wait()
        self.procs = []


def percentiles(xs: list[float]) -> dict[str, float]:
    xs = sorted(xs)
    pick = lambda q: xs[min(len(xs) - 1, int(q * len(xs)))]  # noqa: E731
    return {
        "p50_ms": pick(0.5) * 1e3,
        "p90_ms": pick(0.9) * 1e3,
        "p99_ms": pick(0.99) * 1e3,
        "n": len(xs),
    }


def rss_kib(pid: int) -> int:
    for line in open(f"/proc/{pid}/status"):
        if line.startswith("VmRSS:"):
            return int(line.split()[1])
    return 0


def session_with_agent(domain: int, name: str):
    ros = RosSession(name=name, domain_id=domain)
    agent = DsrAgent()
    agent.setup(ros.node, timeout_sec=60)
    ros.spin_until(lambda: agent.ready, 60, "the server")
    return ros, agent


def extra_agent(ros, name: str) -> DsrAgent:
    """Another node in ``ros`` with a DSR replica of its own, synced."""
    node = __import__("rclpy").create_node(name, context=ros.context)
    ros.executor.add_node(node)
    agent = DsrAgent()
    agent.setup(node, timeout_sec=30)
    ros.spin_until(lambda: agent.ready, 30, name)
    return agent


def timed_reader(ros):
    """A second node in ``ros`` with a DSR replica: (node, agent, {delta id: when it arrived})."""
    reader = extra_agent(ros, "bench_reader")
    reader_node = reader.node
    arrived: dict[str, float] = {}
    reader.add_listener(
        lambda deltas, _: arrived.update({d["id"]: time.perf_counter() for d in deltas})
    )
    return reader_node, reader, arrived


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


def median_ms(xs: list[float]) -> float:
    return statistics.median(xs) * 1e3


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


# ---------------------------------------------------------------------------- 2. throughput
def _wait_ready(p: subprocess.Popen, timeout: float = 60) -> None:
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        line = p.stdout.readline()
        if line.strip() == "ready":
            return
        if not line and p.poll() is not None:
            raise RuntimeError("a counter died before it was ready")
    raise RuntimeError("a counter was not ready in time")


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


def bench_throughput(
    work: Path, domain: int, n: int, batch: int, agents_list: list[int]
) -> dict[str, Any]:
    results: dict[str, Any] = {}
    for k in agents_list:
        procs = Procs(work, domain)
        try:
            procs.server(work / f"tp_state_{k}")
            ros, writer = session_with_agent(domain, "bench_writer")
            counters = [
                procs.start(
                    f"counter{k}_{i}", [sys.executable, str(HERE / "counter.py"), str(n + 1)]
                )
                for i in range(k)
            ]
            for c in counters:
                _wait_ready(c)
            ok = []
            writer.send(
                {"ops": [{"op": "insert_node", "name": "bench", "type": "transform"}]}, ok.append
            )
            ros.spin_until(lambda ok=ok: ok, 10, "set-up")
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
            procs.server(work / f"tpb_state_{k}")
            ros, writer = session_with_agent(domain, "bench_writer")
            m = max(1, n // batch)
            counters = [
                procs.start(
                    f"counterb{k}_{i}", [sys.executable, str(HERE / "counter.py"), str(m + 1)]
                )
                for i in range(k)
            ]
            for c in counters:
                _wait_ready(c)
            ok = []
            writer.send(
                {"ops": [{"op": "insert_node", "name": "bench", "type": "transform"}]}, ok.append
            )
            ros.spin_until(lambda ok=ok: ok, 10, "set-up")
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


# ---------------------------------------------------------------------------- 3. scale
def build_world(n: int, seed: int = 1) -> Graph:
    """n nodes: a random RT tree over a tenth of them, the rest symbolic with a few edges each."""
    rnd = random.Random(seed)
    g = Graph()
    ops: list[dict[str, Any]] = [{"op": "insert_node", "name": "world", "type": "world"}]
    geometric = max(2, n // 10)
    for i in range(1, n):
        ops.append(
            {
                "op": "insert_node",
                "name": f"n{i}",
                "type": "transform" if i < geometric else "state",
                "attrs": {"level": i},
            }
        )
    for i in range(1, geometric):
        parent = "world" if i == 1 else f"n{rnd.randrange(1, i)}"
        ops.append(
            {
                "op": "insert_edge",
                "from": parent,
                "to": f"n{i}",
                "type": "RT",
                "rt": {
                    "translation": [rnd.uniform(-1, 1), 0.0, 0.0],
                    "rotation_euler_xyz": [0.0, 0.0, 0.1],
                },
            }
        )
    for i in range(geometric, n):
        ops.append(
            {
                "op": "insert_edge",
                "from": f"n{i}",
                "to": f"n{rnd.randrange(1, n - 1) or 1}",
                "type": "has",
            }
            if rnd.random() < 0.5
            else {"op": "set_node_attrs", "node": f"n{i}", "attrs": {"pos_x": 1.0}}
        )
    with_edges = [op for op in ops if not (op["op"] == "insert_edge" and op["from"] == op["to"])]
    for start in range(0, len(with_edges), 5000):
        try:
            apply_ops(g, with_edges[start : start + 5000])
        except Exception:  # a random duplicate edge: apply the chunk one by one
            for op in with_edges[start : start + 5000]:
                try:
                    apply_ops(g, [op])
                except Exception:
                    pass
    return g


def late_join(work: Path, domain: int, tag: str, text: str) -> tuple[float, float, int]:
    """A server holding the snapshot ``text`` as its world, and late joiners: seconds to a
    replica synced (the median of three), then to every node and edge of the last one used;
    the server's RSS (KiB)."""
    world = work / f"world_{tag}.json"
    world.write_text(text)
    procs = Procs(work, domain)
    try:
        server = procs.server(work / f"scale_state_{tag}", str(world))
        ros = RosSession(name="bench_late", domain_id=domain)
        from dsr_msgs.srv import GetSnapshot

        client = ros.node.create_client(GetSnapshot, "dsr/get_snapshot")
        # the server is up, and has encoded the snapshot as joiners ask for it (DsrAgent)
        ros.call(client, GetSnapshot.Request(layout="columns"), 300, "the server to load")
        server_rss = rss_kib(server.pid)
        joins = []
        for _ in range(3):  # the median of three joiners, one after the other
            t = time.perf_counter()
            agent = DsrAgent()
            agent.setup(ros.node, timeout_sec=60)
            ros.spin_until(lambda agent=agent: agent.replica.synced, 120, "the snapshot")
            joins.append(time.perf_counter() - t)
        late_s = statistics.median(joins)
        # the replica builds its nodes as they are used, and its edges' indexes at the first
        # edge used: what using all of it costs on top
        t = time.perf_counter()
        sum(1 for _ in agent.replica.graph.nodes())
        agent.replica.graph.edge_count()
        built_s = time.perf_counter() - t
        ros.close()
    finally:
        procs.stop_all()
    world.unlink()
    print(f"  [late join {tag}: {', '.join(f'{j:.3f}' for j in joins)} s]", flush=True)
    return late_s, built_s, server_rss


def bench_scale(work: Path, domain: int, sizes: list[int], ops: int) -> dict[str, Any]:
    out: dict[str, Any] = {}
    for n in sizes:
        gc.collect()
        tracemalloc.start()
        g = build_world(n)
        current, _ = tracemalloc.get_traced_memory()
        tracemalloc.stop()
        names = [f"n{i}" for i in range(1, n)]
        rnd = random.Random(2)
        t = time.perf_counter()
        for i in range(ops):
            apply_ops(
                g, [{"op": "set_node_attrs", "node": rnd.choice(names), "attrs": {"level": i}}]
            )
        attr_us = (time.perf_counter() - t) / ops * 1e6
        t = time.perf_counter()
        for _ in range(ops // 2):
            a, b = rnd.choice(names), rnd.choice(names)
            if a != b and g.edge(a, b, "is") is None:
                apply_ops(g, [{"op": "insert_edge", "from": a, "to": b, "type": "is"}])
                apply_ops(g, [{"op": "delete_edge", "from": a, "to": b, "type": "is"}])
        edge_us = (time.perf_counter() - t) / ops * 1e6
        text = json.dumps(dsr_json.to_json(g, "snapshot", seq=0), separators=(",", ":"))
        late_s, built_s, server_rss = late_join(work, domain, f"{n}", text)
        out[str(n)] = {
            "set_attr_us_per_op": attr_us,
            "edge_us_per_op": edge_us,
            "snapshot_bytes": len(text),
            "late_joiner_s": late_s,
            "late_joiner_then_all_used_s": late_s + built_s,
            "model_bytes_per_node": current / n,
            "server_rss_kib": server_rss,
            "server_rss_bytes_per_node": server_rss * 1024 / n,
        }
        if n == sizes[-1]:  # as a server's graph holds it: every attribute stamped (section 10)
            from cortex import stamp_everything

            stamp_everything(g)
            text = json.dumps(dsr_json.to_json(g, "snapshot", seq=0), separators=(",", ":"))
            stamped_s, _, _ = late_join(work, domain, f"{n}_stamped", text)
            out[str(n)]["stamped_snapshot_bytes"] = len(text)
            out[str(n)]["stamped_late_joiner_s"] = stamped_s
        del g, text
    small, big = out[str(sizes[0])], out[str(sizes[-1])]
    flat = (
        big["set_attr_us_per_op"] <= 1.5 * small["set_attr_us_per_op"]
        and big["edge_us_per_op"] <= 1.5 * small["edge_us_per_op"]
    )
    joins = {"10000": 0.05, "100000": 0.3}  # issue 26: seconds to a late joiner
    joined = all(out[n]["late_joiner_s"] < limit for n, limit in joins.items() if n in out)
    return {
        "sizes": out,
        "targets": "cost per op flat (within 1.5x) from the smallest to the largest graph; "
        "a late joiner synced in < 0.05 s at 10k nodes, < 0.3 s at 100k",
        "met": bool(flat and joined),
    }


# ---------------------------------------------------------------------------- 4. kinematics
def bench_kinematics(depths: list[int], queries: int) -> dict[str, Any]:
    out: dict[str, Any] = {}
    rnd = random.Random(3)
    for d in depths:
        g = Graph()
        ops: list[dict[str, Any]] = [{"op": "insert_node", "name": "root", "type": "world"}]
        for branch in "ab":
            parent = "root"
            for i in range(d):
                name = f"{branch}{i}"
                ops.append({"op": "insert_node", "name": name, "type": "transform"})
                ops.append(
                    {
                        "op": "insert_edge",
                        "from": parent,
                        "to": name,
                        "type": "RT",
                        "rt": {
                            "translation": [rnd.uniform(-1, 1) for _ in range(3)],
                            "rotation_euler_xyz": [rnd.uniform(-3, 3) for _ in range(3)],
                        },
                    }
                )
                parent = name
        apply_ops(g, ops)
        a, b = f"a{d - 1}", f"b{d - 1}"

        def naive(g=g, a=a, b=b) -> np.ndarray:  # the chain from the edges, general inverses
            def up(n):
                m = np.eye(4)
                while True:
                    p = g.rt_parent(n)
                    if p is None:
                        return m
                    m = g.edge(p.name, n, "RT").rt @ m
                    n = p.name

            return np.linalg.inv(up(a)) @ up(b)

        t = time.perf_counter()
        for _ in range(queries):
            g._tree.clear_cache()  # cold: every pose recomputed from the edges
            g.transform(a, b)
        cold = queries / (time.perf_counter() - t)
        g.transform(a, b)
        t = time.perf_counter()
        for _ in range(queries):
            g.transform(a, b)
        cached = queries / (time.perf_counter() - t)
        t = time.perf_counter()
        for _ in range(max(1, queries // 10)):
            ref = naive()
        naive_qps = max(1, queries // 10) / (time.perf_counter() - t)
        assert np.allclose(ref, g.transform(a, b), atol=1e-9)
        rigid.check_rigid(g.transform(a, b))
        out[str(d)] = {"cold_qps": cold, "cached_qps": cached, "naive_qps": naive_qps}
    return {
        "depths": out,
        "targets": ">= 100k cached transform queries/s",
        "met": all(v["cached_qps"] >= 100_000 for v in out.values()),
    }


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


# ---------------------------------------------------------------------------- 7. signed
@contextlib.contextmanager
def security(mode: str, keystore: Path):
    """DSR_SECURITY (and DSR_KEYSTORE) for this process and the ones it starts, then as before."""
    saved = {k: os.environ.get(k) for k in ("DSR_SECURITY", "DSR_KEYSTORE")}
    os.environ["DSR_SECURITY"] = mode
    if mode == "off":
        os.environ.pop("DSR_KEYSTORE", None)
    else:
        os.environ["DSR_KEYSTORE"] = str(keystore)
    try:
        yield
    finally:
        for k, v in saved.items():
            if v is None:
                os.environ.pop(k, None)
            else:
                os.environ[k] = v


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


# ---------------------------------------------------------------------------- 6. get up & go
def cpu_seconds(pid: int) -> float:
    fields = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")


def latency_samples(ros, writer, arrived, n: int, change, step=lambda: None) -> list[float]:
    """Seconds from sending ``change(i)`` until the reader's replica applied it, for i < n, the
    first tenth left out (warming up); ``step`` runs while waiting (another stream)."""
    samples = []
    for i in range(n):
        tx = change(i)
        sent = time.perf_counter()
        ident = writer.send(tx)
        while ident not in arrived:  # the stream goes on while we wait
            step()
            ros.executor.spin_once(timeout_sec=0.0005)
            if time.perf_counter() - sent > 10:
                raise RuntimeError("a change was not seen within 10 s")
        samples.append(arrived[ident] - sent)
    return samples[n // 10 :]


@contextlib.contextmanager
def busy_cores(count: int):
    """``count`` processes spinning on a core each, for as long as the block runs."""
    spinners = [
        subprocess.Popen([sys.executable, "-c", "while True: pass"], start_new_session=True)
        for _ in range(count)
    ]
    try:
        yield
    finally:
        for p in spinners:
            p.kill()
            p.wait()


class SkeletonStream:
    """Person at 30 Hz, as it writes (frames taken while a transaction is in flight go together in
    the next, ``frames_tx``): ``step()`` offers a frame when one is due and sends what waits."""

    def __init__(self, person: DsrAgent, ros):
        from clarc_agents.gug.skeleton import frames_tx, parse_skeleton
        from clarc_sim.devices.skeleton_frames import KinectModel, TrialPlace, skeleton
        from clarc_sim.patient.gait_motion import Motion

        done: list = []
        person.send(
            {
                "ops": [
                    {"op": "insert_node", "name": "person", "type": "person", "attrs": {}},
                    {
                        "op": "insert_edge",
                        "from": "kinect",
                        "to": "person",
                        "type": "RT",
                        "rt": {"translation": [4.3, 0, -0.7], "rotation_euler_xyz": [0, 0, 0]},
                    },
                ]
            },
            done.append,
        )
        ros.spin_until(lambda: done, 10, "the person")
        self.motion = Motion(reaction=1.0, rise=2.0, walk_out=4.0, turn=2.0, walk_back=4.0, sit=3.0)
        place, sensor = (
            TrialPlace(4500.0, 0.0, -1200.0, 3.14159),
            KinectModel(random.Random(3), 10.0),
        )
        self.frame = lambda t: parse_skeleton(sensor.see(skeleton(self.motion, t, place), t)[0])
        self.frames_tx, self.person = frames_tx, person
        self.restart()

    def restart(self) -> None:
        self.next, self.frames, self.written, self.txs, self.volatile = (
            time.perf_counter(),
            0,
            0,
            0,
            0,
        )
        self.waiting: list = []
        self.in_flight = False

    def step(self) -> None:
        now = time.perf_counter()
        if now >= self.next:
            # a frame every 1/30 s from now on; frames not offered while we did not run are
            # lost, as a Kinect's are
            self.next = max(self.next, now - 1.0 / 30.0) + 1.0 / 30.0
            self.frames += 1
            t = (self.frames / 30.0) % (self.motion.total + 3.0) - 1.0
            self.waiting.append((self.frame(t), time.time()))
        if self.in_flight or not self.waiting:
            return
        batch, self.waiting = self.waiting, []
        self.in_flight = True

        def written(r) -> None:
            self.in_flight = False
            self.txs += 1
            self.written += len(batch) if r.accepted else 0
            self.volatile += bool(r.accepted and "volatile" in r.delta)

        self.person.send(self.frames_tx(self.person.graph, batch), written)

    def delta_bytes(self) -> int:
        return len(json.dumps(self.frames_tx(self.person.graph, [(self.frame(0.0), time.time())])))


def server_cpu(server, ros, seconds: float, run) -> float:
    """The server's share of a core while ``run()`` is called for ``seconds``."""
    before, t0 = cpu_seconds(server.pid), time.perf_counter()
    while time.perf_counter() - t0 < seconds:
        run()
        ros.executor.spin_once(timeout_sec=0.001)
    return (cpu_seconds(server.pid) - before) / (time.perf_counter() - t0)


def speech_change(i: int) -> dict[str, Any]:
    """A Speech-sized change."""
    return {"ops": [{"op": "set_node_attrs", "node": "test", "attrs": {"item": f"x{i}"}}]}


def gug_stream(work: Path, domain: int, seconds: float, n: int) -> dict[str, Any]:
    """A patient's skeleton at 30 Hz written as Person writes it: the server's CPU, frames
    written of those offered, a Speech-sized change's latency and the journal's growth, each
    against the same without the stream."""
    procs = Procs(work, domain)
    state = work / f"gug_state_{domain}"
    out: dict[str, Any] = {}
    try:
        server = procs.server(state, str(ROOT / "worlds" / "clarc_room.json"))
        ros, person = session_with_agent(domain, "person")
        _, _, arrived = timed_reader(ros)
        speech = extra_agent(ros, "speech")  # Speech's change from its own node, as in a launch
        stream = SkeletonStream(person, ros)
        out["server_cpu_idle"] = server_cpu(server, ros, seconds, lambda: None)
        stream.restart()
        journal = state / "journal.jsonl"
        size0, t0 = journal.stat().st_size if journal.exists() else 0, time.perf_counter()
        largest, sizes = [size0], {"last": size0, "grown": 0}

        def streaming() -> None:
            stream.step()
            if journal.exists():
                size = journal.stat().st_size
                largest[0] = max(largest[0], size)
                # appended since the last look (after a compaction: the new journal's size)
                sizes["grown"] += size - sizes["last"] if size >= sizes["last"] else size
                sizes["last"] = size

        out["server_cpu_streaming"] = server_cpu(server, ros, seconds, streaming)
        elapsed = time.perf_counter() - t0
        out["frames_written_per_s"] = stream.written / elapsed
        out["frames_offered_per_s"] = stream.frames / elapsed
        out["frames_per_tx"] = stream.written / max(stream.txs, 1)
        out["delta_bytes"] = stream.delta_bytes()
        out["volatile_share"] = stream.volatile / max(stream.txs, 1)
        out["journal_bytes_per_min"] = sizes["grown"] / elapsed * 60
        out["journal_largest_bytes"] = largest[0]
        out["compact_every"] = 1000
        out["latency_quiet"] = percentiles(latency_samples(ros, speech, arrived, n, speech_change))
        out["latency_streaming"] = percentiles(
            latency_samples(ros, speech, arrived, n, speech_change, stream.step)
        )
        ros.close()
    finally:
        procs.stop_all()
    return out


# ---------------------------------------------------------------------------- 7. camera
class CameraStream:
    """The camera agent at 30 Hz: a 640x480 colour image and a depth image (float32 metres) of
    the room, at most two transactions on their way, each with the newest images."""

    def __init__(self, camera: DsrAgent):
        from clarc_sim.devices.camera_images import CameraModel

        self.model, self.camera = CameraModel(640, 480), camera
        self.restart()

    def restart(self) -> None:
        self.next, self.offered, self.written, self.in_flight = time.perf_counter(), 0, 0, 0
        self.pending: dict[str, Any] | None = None

    def step(self) -> None:
        now = time.perf_counter()
        if now >= self.next:
            self.next = max(self.next, now - 1.0 / 30.0) + 1.0 / 30.0
            rgb, depth = self.model.frame(self.offered, (1500.0, 0.0, 300.0))
            self.offered += 1
            attrs = {"cam_rgb": rgb, "cam_depth": depth.astype(np.float32) * np.float32(0.001)}
            self.pending = {"ops": [{"op": "set_node_attrs", "node": "kinect", "attrs": attrs}]}
        if self.pending is None or self.in_flight >= 2:
            return
        tx, self.pending = self.pending, None
        self.in_flight += 1

        def written(r) -> None:
            self.in_flight -= 1
            self.written += bool(r.accepted)

        self.camera.send(tx, written)


def hop_costs(repeat: int = 20) -> dict[str, float]:
    """What one hop costs a camera frame (both images) in this process, ms: as JSON text with
    base64 (encode and decode back to arrays), and as blobs beside a small JSON (the bytes copied
    and hashed, the JSON encoded and decoded, the arrays made over the bytes)."""
    from dsr_graph.model.binary import array_coercer, dumps
    from dsr_graph.protocol.blobs import extract, resolve

    rgb = np.random.default_rng(1).integers(0, 256, (480, 640, 3), dtype=np.uint8)
    depth = np.full((480, 640), 1.5, dtype=np.float32)
    delta = {
        "ops": [
            {"op": "set_node_attrs", "node": "k", "attrs": {"cam_rgb": rgb, "cam_depth": depth}}
        ]
    }
    times: dict[str, list[float]] = {"inline_ms": [], "blob_ms": []}
    for _ in range(repeat):
        t0 = time.perf_counter()
        doc = json.loads(dumps(delta))
        attrs = doc["ops"][0]["attrs"]
        array_coercer("uint8_array")(attrs["cam_rgb"])
        array_coercer("float32_array")(attrs["cam_depth"])
        t1 = time.perf_counter()
        out, blobs = extract(delta)
        doc = resolve(json.loads(dumps(out)), blobs.get)
        t2 = time.perf_counter()
        times["inline_ms"].append((t1 - t0) * 1e3)
        times["blob_ms"].append((t2 - t1) * 1e3)
    text = len(dumps(delta))
    return {k: sorted(v)[len(v) // 2] for k, v in times.items()} | {"inline_json_bytes": text}


def bench_camera(work: Path, domain: int, seconds: float, n: int) -> dict[str, Any]:
    """The camera (640x480 colour and depth, 30 Hz) and the skeleton (30 Hz) streaming into the
    DSR together: the server's CPU, images offered, written and delivered whole to a replica that
    asks for the bytes (another process), and a Speech-sized change's latency, each against the
    same without the streams; and what one hop costs a frame as base64 JSON or as blobs."""
    procs = Procs(work, domain)
    out: dict[str, Any] = {"hop": hop_costs()}
    try:
        server = procs.server(
            work / f"camera_state_{domain}", str(ROOT / "worlds" / "clarc_room.json")
        )
        ros, camera = session_with_agent(domain, "camera")
        _, _, arrived = timed_reader(ros)
        person, speech = (extra_agent(ros, name) for name in ("person", "speech"))
        skeleton, images = SkeletonStream(person, ros), CameraStream(camera)
        out["server_cpu_idle"] = server_cpu(server, ros, seconds, lambda: None)
        # Speech's change from Speech's own node, as in a launch (from the camera's it queued
        # behind the images on the camera's request topic)
        out["latency_quiet"] = percentiles(latency_samples(ros, speech, arrived, n, speech_change))
        counter = procs.start(
            "image_counter", [sys.executable, str(HERE / "image_counter.py"), str(seconds)]
        )
        _wait_ready(counter)

        def streaming() -> None:
            images.step()
            skeleton.step()

        skeleton.restart()
        images.restart()
        t0 = time.perf_counter()
        out["server_cpu_streaming"] = server_cpu(server, ros, seconds, streaming)
        elapsed = time.perf_counter() - t0
        counted = json.loads(counter.stdout.readline() or counter.communicate(timeout=30)[0])
        out["frames_offered_per_s"] = images.offered / elapsed
        out["frames_written_per_s"] = images.written / elapsed
        out["frames_delivered_per_s"] = counted["whole"] / counted["seconds"]
        out["frames_unfetched"] = counted["unfetched"]
        out["reader_resyncs"] = counted["resyncs"]
        out["skeleton_frames_written_per_s"] = skeleton.written / elapsed
        out["latency_streaming"] = percentiles(
            latency_samples(ros, speech, arrived, n, speech_change, streaming)
        )
        ros.close()
    finally:
        procs.stop_all()
    return out


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
    work: Path, domain: int, seconds: float, n: int, scale: float, scenarios: bool
) -> dict[str, Any]:
    """The skeleton stream's load on the DSR and a whole GUG run's CPU, quiet; and the same
    with every core kept busy by another process (``under_load``): frames written of those
    offered, a Speech change's latency, and (``scenarios``) what each shipped GUG scenario
    stored, quiet and loaded."""
    out = gug_stream(work, domain, seconds, n)
    out["robot"] = bench_barthel(work, scale, ROOT / "scenarios" / "gug_normal.yaml", db="gug.db")
    cores = os.cpu_count() or 2
    with busy_cores(cores):
        loaded = gug_stream(work, domain, seconds, n)
    out["under_load"] = {"busy_processes": cores} | {
        k: loaded[k]
        for k in (
            "server_cpu_streaming",
            "frames_written_per_s",
            "frames_offered_per_s",
            "frames_per_tx",
            "latency_quiet",
            "latency_streaming",
        )
    }
    if scenarios:
        out["scenarios"] = {"pace": scale, "quiet": gug_runs(work, scale, "quiet")}
        with busy_cores(cores):
            out["scenarios"]["loaded"] = gug_runs(work, scale, "loaded")
    return out


# ---------------------------------------------------------------------------- the report
def table(report: dict[str, Any]) -> str:
    lines = []
    if report.get("speech"):
        from speech import table as speech_table

        lines += speech_table(report["speech"])
    lat = report.get("latency")
    if lat:
        lines.append("change-to-visible latency (2 hops)    p50        p90        p99")
        for k in ("dsr", "volatile", "raw", "fdatasync"):
            v = lat[k]
            lines.append(
                f"  {k:<35} {v['p50_ms']:6.3f} ms  {v['p90_ms']:6.3f} ms  {v['p99_ms']:6.3f} ms"
            )
        paced = lat.get("fdatasync_paced")
        if paced:
            lines.append(f"  {'fdatasync, 1 ms apart':<35} {paced['p50_ms']:6.3f} ms")
        for kind, steps in lat.get("stages", {}).items():
            shown = ", ".join(f"{k[:-3]} {v:.3f}" for k, v in steps.items())
            lines.append(f"  {kind} steps (p50 ms): {shown}")
        lines.append(
            f"  symbolic/raw p50 {lat['ratio_p50']:.2f}x, p99 {lat['ratio_p99']:.2f}x; symbolic/"
            f"(raw + fdatasync) p50 {lat['ratio_p50_durable_floor']:.2f}x; volatile/raw p50 "
            f"{lat['ratio_p50_volatile']:.2f}x  (target {lat['targets']}: "
            f"{'met' if lat['met'] else 'NOT met'})"
        )
    tp = report.get("throughput")
    if tp:
        lines.append(
            "throughput                 agents  dsr tx/s  dsr ops/s (batched)  raw msgs/s"
            "  (deltas applied / messages received by every subscriber)"
        )
        for k, v in tp["agents"].items():
            note = ""
            if v.get("dsr_resyncs") or v.get("dsr_delivered", 1) < 1:
                note = (
                    f"  dsr: {v['dsr_delivered']:.0%} applied one by one, "
                    f"{v['dsr_resyncs']} resync(s) from a snapshot"
                )
            if v["raw_delivered"] < 1:
                note += f"  raw: {v['raw_delivered']:.0%} received"
            lines.append(
                f"  {'':<24} {k:>6}  {v['dsr_tx_per_s']:8.0f}  "
                f"{v['dsr_batched_ops_per_s']:19.0f}  {v['raw_msgs_per_s']:10.0f}{note}"
            )
        lines.append(f"  target {tp['targets']}: {'met' if tp['met'] else 'NOT met'}")
    sc = report.get("scale")
    if sc:
        lines.append(
            "scale        nodes  set_attr us/op  edge us/op  snapshot MB  late joiner s  "
            "then all used s  model B/node  server RSS B/node"
        )
        for k, v in sc["sizes"].items():
            lines.append(
                f"  {'':<9} {k:>7}  {v['set_attr_us_per_op']:14.1f}  {v['edge_us_per_op']:10.1f}  "
                f"{v['snapshot_bytes'] / 1e6:11.2f}  {v['late_joiner_s']:13.3f}  "
                f"{v['late_joiner_then_all_used_s']:15.3f}  "
                f"{v['model_bytes_per_node']:12.0f}  "
                f"{v['server_rss_bytes_per_node']:16.0f}"
            )
        stamped = [(k, v) for k, v in sc["sizes"].items() if "stamped_late_joiner_s" in v]
        for k, v in stamped:
            lines.append(
                f"  {k} nodes, every attribute stamped (provenance): snapshot "
                f"{v['stamped_snapshot_bytes'] / 1e6:.2f} MB, late joiner "
                f"{v['stamped_late_joiner_s']:.3f} s"
            )
        lines.append(f"  target {sc['targets']}: {'met' if sc['met'] else 'NOT met'}")
    if report.get("provenance"):
        from cortex import provenance_lines

        lines += provenance_lines(report["provenance"])
    if report.get("rt_history"):
        from cortex import rt_history_lines

        lines += rt_history_lines(report["rt_history"])
    kin = report.get("kinematics")
    if kin:
        lines.append("kinematics   depth  cold q/s  cached q/s  naive numpy q/s")
        for k, v in kin["depths"].items():
            lines.append(
                f"  {'':<9} {k:>5}  {v['cold_qps']:8.0f}  {v['cached_qps']:10.0f}  "
                f"{v['naive_qps']:15.0f}"
            )
        lines.append(f"  target {kin['targets']}: {'met' if kin['met'] else 'NOT met'}")
    b = report.get("barthel")
    if b:
        lines.append(
            f"barthel run (pace x{b['pace']}): completed {b['completed']}, test {b['test_s']} s, "
            f"launch wall {b['wall_s']:.1f} s, CPU {b['cpu_total_s']:.1f} s in all"
        )
        lines.append(
            "  "
            + ", ".join(
                f"{k} {v:.1f}s" for k, v in sorted(b["cpu_s"].items(), key=lambda kv: -kv[1])
            )
        )
    g = report.get("gug")
    if g:
        q, st = g["latency_quiet"], g["latency_streaming"]
        lines.append(
            f"get up & go: skeleton at 30 Hz, 14 joints ({g['frames_written_per_s']:.1f} frames/s "
            f"written of {g['frames_offered_per_s']:.1f}, {g['frames_per_tx']:.1f} a "
            f"transaction, {g['delta_bytes']} B for one)"
        )
        lines.append(
            f"  server CPU {g['server_cpu_streaming']:.1%} streaming vs {g['server_cpu_idle']:.1%}"
            " idle"
        )
        lines.append(
            f"  a Speech change's latency p50/p99 {st['p50_ms']:.3f}/{st['p99_ms']:.3f} ms "
            f"streaming vs {q['p50_ms']:.3f}/{q['p99_ms']:.3f} ms quiet"
        )
        lines.append(
            f"  journal: {g['journal_bytes_per_min'] / 1e3:.1f} kB/min while it streams "
            f"({g['volatile_share']:.0%} of the frames' transactions volatile, not journalled), "
            f"largest {g['journal_largest_bytes'] / 1e3:.1f} kB (compaction every "
            f"{g['compact_every']} journalled deltas)"
        )
        u = g["under_load"]
        ul, uq = u["latency_streaming"], u["latency_quiet"]
        lines.append(
            f"  under load ({u['busy_processes']} busy processes): "
            f"{u['frames_written_per_s']:.1f} frames/s written of "
            f"{u['frames_offered_per_s']:.1f}, {u['frames_per_tx']:.1f} a transaction; a Speech "
            f"change p50/p99 {ul['p50_ms']:.3f}/{ul['p99_ms']:.3f} ms streaming vs "
            f"{uq['p50_ms']:.3f}/{uq['p99_ms']:.3f} ms without the stream"
        )
        for load, runs in (
            (k, v) for k, v in g.get("scenarios", {}).items() if isinstance(v, dict)
        ):
            lines.append(f"  GUG scenarios at pace x{g['scenarios']['pace']}, {load}:")
            for name, v in runs.items():
                timed = f"{v['tug_seconds']:.1f} s" if v["tug_seconds"] is not None else "-"
                lines.append(
                    f"    {name:<24} {v['outcome'] or 'nothing stored':<8} {timed:>7}  "
                    f"trials {v['trials']}  wall {v['wall_s']:.0f} s"
                )
        r = g["robot"]
        lines.append(
            f"  whole robot over a GUG run (pace x{r['pace']}): completed {r['completed']}, CPU "
            f"{r['cpu_total_s']:.1f} s in all, launch wall {r['wall_s']:.1f} s"
            + (f" (Barthel run: {b['cpu_total_s']:.1f} s, {b['wall_s']:.1f} s)" if b else "")
        )
        lines.append(
            "  "
            + ", ".join(
                f"{k} {v:.1f}s" for k, v in sorted(r["cpu_s"].items(), key=lambda kv: -kv[1])
            )
        )
    c = report.get("camera")
    if c:
        q, st, hop = c["latency_quiet"], c["latency_streaming"], c["hop"]
        lines.append(
            f"camera: 640x480 colour + depth at 30 Hz with the skeleton at 30 Hz: images "
            f"{c['frames_offered_per_s']:.1f}/s offered, {c['frames_written_per_s']:.1f} written, "
            f"{c['frames_delivered_per_s']:.1f} delivered whole to a replica that asks for the "
            f"bytes ({c['frames_unfetched']} not in time, {c['reader_resyncs']} resyncs); "
            f"skeleton {c['skeleton_frames_written_per_s']:.1f} frames/s written"
        )
        lines.append(
            f"  server CPU {c['server_cpu_streaming']:.1%} streaming vs {c['server_cpu_idle']:.1%}"
            f" idle; a Speech change p50/p99 {st['p50_ms']:.3f}/{st['p99_ms']:.3f} ms streaming "
            f"vs {q['p50_ms']:.3f}/{q['p99_ms']:.3f} ms quiet "
            f"(p99 x{st['p99_ms'] / q['p99_ms']:.2f})"
        )
        lines.append(
            f"  one hop of a frame: {hop['blob_ms']:.2f} ms as blobs vs {hop['inline_ms']:.2f} ms "
            f"as base64 JSON ({hop['inline_json_bytes'] / 1e6:.1f} MB of text)"
        )
    signed = report.get("signed")
    if signed:
        lines.append("signed DSR traffic (enforce) next to unsigned (off), same run")
        for mode in ("off", "enforce"):
            v = signed[mode]
            lines.append(
                f"  {mode:<8} latency p50 {v['latency']['p50_ms']:.3f} ms, p99 "
                f"{v['latency']['p99_ms']:.3f} ms; {v['tx_per_s']:,.0f} tx/s (1 agent); "
                f"Barthel run {v['barthel_cpu_s']:.1f} CPU s (server "
                f"{v['barthel_server_cpu_s'] or 0:.1f})"
                + ("" if v["barthel_completed"] else "  [the run did not complete]")
            )
        c = signed["cost"]
        lines.append(
            f"  cost: p50 {c['p50_ms']:+.3f} ms, p99 {c['p99_ms']:+.3f} ms, throughput "
            f"x{c['throughput_ratio']:.2f}, Barthel CPU x{c['barthel_cpu_ratio']:.2f}"
        )
    return "\n".join(lines)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument(
        "--quick",
        action="store_true",
        help="about 4 minutes: fewer samples, sizes up to 10k, 1 and 8 agents, a Barthel run "
        "at pace x0.05, no Get Up & Go scenarios",
    )
    parser.add_argument("--out", default=str(ROOT / "bench-results" / "bench.json"))
    parser.add_argument("--only", nargs="*", help="sections to run (default all)")
    args = parser.parse_args()
    quick = args.quick
    sections = set(
        args.only
        or [
            "latency",
            "throughput",
            "scale",
            "kinematics",
            "barthel",
            "gug",
            "camera",
            "signed",
            "speech",
            "speech_loop",
            "provenance",
            "rt_history",
        ]
    )
    domain = 10 + os.getpid() % 90
    report: dict[str, Any] = {
        "machine": {
            "cpus": os.cpu_count(),
            "python": platform.python_version(),
            "platform": platform.platform(),
            "cpu": next(
                (
                    line.split(":", 1)[1].strip()
                    for line in open("/proc/cpuinfo")
                    if line.startswith("model name")
                ),
                "",
            ),
        },
        "mode": "quick" if quick else "full",
        "when": time.strftime("%Y-%m-%dT%H:%M:%S%z"),
    }
    with tempfile.TemporaryDirectory() as tmp:
        work = Path(tmp)
        if "kinematics" in sections:
            report["kinematics"] = bench_kinematics([2, 10, 50], 2000 if quick else 20000)
        if "latency" in sections:
            report["latency"] = bench_latency(work, domain, 200 if quick else 2000)
        if "throughput" in sections:
            report["throughput"] = bench_throughput(
                work, domain, 1000 if quick else 5000, 100, [1, 8] if quick else [1, 4, 8]
            )
        if "scale" in sections:
            report["scale"] = bench_scale(
                work,
                domain,
                [1000, 10000] if quick else [1000, 10000, 100000],
                2000 if quick else 10000,
            )
        if "barthel" in sections:
            report["barthel"] = bench_barthel(work, 0.05 if quick else 0.1)
        if "gug" in sections:
            report["gug"] = bench_gug(
                work, domain, 5.0 if quick else 20.0, 100 if quick else 500, 0.1, not quick
            )
        if "camera" in sections:
            report["camera"] = bench_camera(
                work, domain, 5.0 if quick else 20.0, 100 if quick else 500
            )
        if "provenance" in sections:
            from cortex import bench_provenance

            report["provenance"] = bench_provenance(
                build_world, [10000] if quick else [10000, 100000], 2000 if quick else 10000
            )
        if "rt_history" in sections:
            from cortex import bench_rt_history

            report["rt_history"] = bench_rt_history([2, 10, 50], 2000 if quick else 20000)
        if "speech" in sections:
            from speech import bench_speech

            report["speech"] = bench_speech(quick)
        if "speech_loop" in sections:
            from speech import bench_speech_loop

            report.setdefault("speech", {})["loop"] = bench_speech_loop(work, domain, ROOT)
        if "signed" in sections:
            report["signed"] = bench_signed(
                work, domain, 200 if quick else 2000, 1000 if quick else 5000, 0.1
            )
    Path(args.out).parent.mkdir(parents=True, exist_ok=True)
    Path(args.out).write_text(json.dumps(report, indent=2))
    print(table(report))
    print(f"\nreport: {args.out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
