"""Transform queries on RT trees of depth 2, 10 and 50, cold and cached, next to naive numpy."""

from __future__ import annotations

import random
import time
from typing import Any

import numpy as np

from dsr_graph.model import rigid
from dsr_graph.model.graph import Graph
from dsr_graph.model.transaction import apply_ops


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
