"""What CORTEX's features cost here (issue 24): provenance on every attribute, next to the same
graph without it (memory, snapshot bytes, the cost of applying a change)."""

from __future__ import annotations

import gc
import json
import random
import time
import tracemalloc
from typing import Any

from dsr_graph.formats import dsr_json
from dsr_graph.model import provenance
from dsr_graph.model.transaction import apply_ops

AGENTS = ["/pelea", "/speech", "/panel", "/person", "/cgamed", "/clarc_start", "/gait", "/x"]


def _attribute_count(g) -> int:
    return sum(len(n.attrs) for n in g.nodes()) + sum(
        len(e.attrs) + (e.rt is not None) for e in g.edges()
    )


def stamp_everything(g) -> None:
    """The worst case: every element last written by a delta of its own (a stamp each)."""
    for i, element in enumerate([*g.nodes(), *g.edges()]):
        mark = (1.7e9 + i * 0.01, AGENTS[i % len(AGENTS)])
        element.prov = {name: mark for name in element.attrs}
        if getattr(element, "rt", None) is not None:
            element.prov[provenance.RT_KEY] = mark


def bench_provenance(build_world, sizes: list[int], ops: int) -> dict[str, Any]:
    out: dict[str, Any] = {}
    for n in sizes:
        gc.collect()
        g = build_world(n)
        attributes = _attribute_count(g)
        plain = len(json.dumps(dsr_json.to_json(g, "snapshot", seq=0), separators=(",", ":")))
        gc.collect()
        tracemalloc.start()
        stamp_everything(g)
        stamped_bytes, _ = tracemalloc.get_traced_memory()
        tracemalloc.stop()
        stamped = len(json.dumps(dsr_json.to_json(g, "snapshot", seq=0), separators=(",", ":")))
        names = [f"n{i}" for i in range(1, n)]
        rnd = random.Random(4)
        batches = [
            [{"op": "set_node_attrs", "node": rnd.choice(names), "attrs": {"level": i}}]
            for i in range(ops)
        ]
        t = time.perf_counter()
        for batch in batches:
            apply_ops(g, batch)
        without = (time.perf_counter() - t) / ops * 1e6
        t = time.perf_counter()
        for i, batch in enumerate(batches):
            provenance.apply_delta(g, {"ops": batch, "stamp": 1.8e9 + i, "agent": "/speech"})
        with_prov = (time.perf_counter() - t) / ops * 1e6
        out[str(n)] = {
            "attributes": attributes,
            "memory_bytes_per_attribute": stamped_bytes / attributes,
            "snapshot_bytes_plain": plain,
            "snapshot_bytes_stamped": stamped,
            "snapshot_bytes_per_attribute": (stamped - plain) / attributes,
            "set_attr_us_plain": without,
            "set_attr_us_stamped": with_prov,
        }
        del g
    return {
        "sizes": out,
        "wire": "a delta carries nothing more: every replica stamps it with its own stamp "
        "and agent",
    }


def provenance_lines(report: dict[str, Any]) -> list[str]:
    lines = [
        "provenance   nodes  attributes  memory B/attr  snapshot MB plain/stamped  "
        "B/attr  set_attr us plain/stamped"
    ]
    for k, v in report["sizes"].items():
        lines.append(
            f"  {'':<9} {k:>7}  {v['attributes']:10d}  {v['memory_bytes_per_attribute']:13.0f}  "
            f"{v['snapshot_bytes_plain'] / 1e6:12.2f} / {v['snapshot_bytes_stamped'] / 1e6:<11.2f}"
            f"  {v['snapshot_bytes_per_attribute']:6.1f}  "
            f"{v['set_attr_us_plain']:10.1f} / {v['set_attr_us_stamped']:.1f}"
        )
    lines.append(f"  on the wire: {report['wire']}")
    return lines


def bench_rt_history(depths: list[int], queries: int, values: int = 100) -> dict[str, Any]:
    """A chain asked at a past time (every edge on it moved ``values`` times, the time between
    two of them) next to today's cached transform and the cold one, on the same graph."""
    from dsr_graph.model.graph import Graph

    out: dict[str, Any] = {}
    rnd = random.Random(5)
    for d in depths:
        g = Graph()
        ops: list[dict[str, Any]] = [{"op": "insert_node", "name": "root", "type": "world"}]
        parent = "root"
        for i in range(d):
            ops.append({"op": "insert_node", "name": f"l{i}", "type": "transform"})
            ops.append(
                {
                    "op": "insert_edge",
                    "from": parent,
                    "to": f"l{i}",
                    "type": "RT",
                    "rt": {"translation": [0.1, 0, 0], "rotation_euler_xyz": [0, 0, 0.1]},
                }
            )
            parent = f"l{i}"
        apply_ops(g, ops)
        g.rt_history.limit(float(values + 1), values)  # a second apart: all of them kept
        for k in range(values):  # every edge moves at each time step
            moves = [
                {
                    "op": "set_rt",
                    "from": "root" if i == 0 else f"l{i - 1}",
                    "to": f"l{i}",
                    "rt": {
                        "translation": [rnd.uniform(-1, 1), 0, 0],
                        "rotation_euler_xyz": [0, 0, rnd.uniform(-3, 3)],
                    },
                }
                for i in range(d)
            ]
            provenance.apply_delta(g, {"ops": moves, "stamp": 1000.0 + k, "agent": "/x"})
        leaf = f"l{d - 1}"
        times = [1000.0 + rnd.uniform(0, values - 1) for _ in range(queries)]  # held times
        t = time.perf_counter()
        for when in times:
            g.transform_at("root", leaf, when)
        past = queries / (time.perf_counter() - t)
        g.transform("root", leaf)
        t = time.perf_counter()
        for _ in range(queries):
            g.transform("root", leaf)
        cached = queries / (time.perf_counter() - t)
        t = time.perf_counter()
        for _ in range(queries):
            g._tree.clear_cache()
            g.transform("root", leaf)
        cold = queries / (time.perf_counter() - t)
        out[str(d)] = {"at_time_q_per_s": past, "cached_q_per_s": cached, "cold_q_per_s": cold}
    return {"depths": out, "values_per_edge": values}


def rt_history_lines(report: dict[str, Any]) -> list[str]:
    lines = [
        f"rt history   depth  at a past time q/s  cached q/s  cold q/s  "
        f"({report['values_per_edge']} values an edge)"
    ]
    for k, v in report["depths"].items():
        lines.append(
            f"  {'':<9} {k:>5}  {v['at_time_q_per_s']:18.0f}  {v['cached_q_per_s']:10.0f}  "
            f"{v['cold_q_per_s']:8.0f}"
        )
    return lines
