"""The DSR's RT tree as tf2 sees it (pure): frame ids are node names, lengths in metres,
quaternions x, y, z, w (REP 103). The edges that never changed since the server started go on
/tf_static; an edge that changes, or appears later, moves to /tf for good, so that tf2 never
holds a frame both as static and as dynamic. The DSR's lengths are already metres (units.py).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from dsr_graph.model import rigid
from dsr_graph.model.graph import Graph
from dsr_graph.model.vocabulary import RT


@dataclass(frozen=True)
class Transform:
    parent: str  # header.frame_id
    child: str  # child_frame_id
    translation: tuple[float, float, float]  # metres
    rotation: tuple[float, float, float, float]  # x, y, z, w


def transform_of(graph: Graph, child: str) -> Transform | None:
    """``child``'s pose in its RT parent's frame, or None if it has no RT parent now."""
    node = graph.find(child)
    parent = graph.rt_parent(child) if node is not None else None
    if parent is None:
        return None
    matrix = graph.edge(parent.id, node.id, RT).rt
    x, y, z = (float(v) for v in matrix[:3, 3])
    w, qx, qy, qz = rigid.quaternion_wxyz(matrix)
    return Transform(parent.name, child, (x, y, z), (qx, qy, qz, w))


def moved_nodes(delta: dict[str, Any]) -> list[str]:
    """Nodes whose pose in their parent's frame this delta changed (or gave)."""
    return [
        op["to"]
        for op in delta["ops"]
        if (op["op"] == "insert_edge" and op["type"] == RT) or op["op"] == "set_rt"
    ]


def _may_remove_rt(delta: dict[str, Any]) -> bool:
    return any(
        op["op"] == "delete_node" or (op["op"] == "delete_edge" and op["type"] == RT)
        for op in delta["ops"]
    )


class TfBook:
    """Which RT edges are static (never changed since ``start``) and which are dynamic."""

    def __init__(self, graph: Graph):
        self.static = {graph.node(e.dst).name for e in graph.edges() if e.type == RT}
        self.dynamic: set[str] = set()

    def static_transforms(self, graph: Graph) -> list[Transform]:
        return [t for c in sorted(self.static) if (t := transform_of(graph, c)) is not None]

    def dynamic_transforms(self, graph: Graph) -> list[Transform]:
        return [t for c in sorted(self.dynamic) if (t := transform_of(graph, c)) is not None]

    def update(self, graph: Graph, delta: dict[str, Any]) -> tuple[list[Transform], bool]:
        """After ``delta`` was applied: the transforms to send on /tf now, and whether the
        static set changed (then /tf_static is sent again, without the edges that left it)."""
        moved = moved_nodes(delta)
        static_changed = bool(self.static.intersection(moved))
        self.static.difference_update(moved)
        self.dynamic.update(moved)
        if _may_remove_rt(delta):
            for names in (self.static, self.dynamic):
                gone = {c for c in names if transform_of(graph, c) is None}
                static_changed |= names is self.static and bool(gone)
                names.difference_update(gone)
        now = [t for c in moved if (t := transform_of(graph, c)) is not None]
        return now, static_changed
