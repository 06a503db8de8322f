"""Graphs of 1k, 10k and 100k nodes: cost per operation, a snapshot to a late joiner, memory."""

from __future__ import annotations

import gc
import json
import random
import statistics
import time
import tracemalloc
from pathlib import Path
from typing import Any

from harness import Procs, rss_kib

from dsr_graph.formats import dsr_json
from dsr_graph.model.graph import Graph
from dsr_graph.model.transaction import apply_ops
from dsr_graph.ros.agent import DsrAgent
from dsr_graph.ros.session import RosSession


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
