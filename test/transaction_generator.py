"""Transactions drawn against the graph as it is: existing names, vocabulary types, attributes of
their declared type, rigid transforms, legal RT moves (a new child under a geometric node,
preferring recent ones so the tree grows deep). Each op is drawn against a scratch copy that the
previous ops of the transaction already changed, so a transaction is valid by construction,
unless it is asked to carry one deliberate mistake (a self-loop, a cycle, a second parent, an
unknown type, a non-rigid matrix, a missing node, an orphaned subtree...). Every choice goes
through a ``Pick``, so the same generator runs under hypothesis (shrinkable) or a seeded
``random.Random`` (reproducible sizes)."""

from __future__ import annotations

import json
import math
import random
from typing import Any, Protocol

from hypothesis import strategies as st

from dsr_graph.formats import dsr_json
from dsr_graph.model.graph import Graph
from dsr_graph.model.transaction import apply_ops


class Pick(Protocol):
    def integer(self, low: int, high: int) -> int: ...
    def real(self, low: float, high: float) -> float: ...
    def choice(self, options: list) -> Any: ...


class HypothesisPick:
    def __init__(self, data):
        self.data = data

    def integer(self, low, high):
        return self.data.draw(st.integers(low, high))

    def real(self, low, high):
        return self.data.draw(st.floats(low, high, allow_nan=False))

    def choice(self, options):
        return self.data.draw(st.sampled_from(options))


class RandomPick:
    def __init__(self, seed: int):
        self.random = random.Random(seed)

    def integer(self, low, high):
        return self.random.randint(low, high)

    def real(self, low, high):
        return self.random.uniform(low, high)

    def choice(self, options):
        return self.random.choice(options)


NOT_RIGID = {"matrix": [[2, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]}
# (kind, weight): the valid kinds dominate; "mistake" draws one of MISTAKES
KINDS = [
    ("insert_node", 22),
    ("insert_edge", 20),
    ("insert_rt", 18),
    ("set_node_attrs", 10),
    ("set_rt", 8),
    ("set_edge_attrs", 4),
    ("delete_edge", 4),
    ("delete_leaf", 3),
    ("remove_node_attrs", 2),
    ("mistake", 9),
]
MISTAKES = [
    "self_loop",
    "rt_cycle",
    "second_parent",
    "unknown_node_type",
    "unknown_edge_type",
    "not_rigid",
    "missing_node",
    "unknown_attribute",
    "orphan_subtree",
    "wrong_attribute_type",
]


class TransactionGenerator:
    def __init__(self, pick: Pick, graph: Graph):
        self.pick = pick
        self.vocabulary = graph.vocabulary
        self.node_types = sorted(t for t in self.vocabulary.node_types)
        self.edge_types = sorted(t for t in self.vocabulary.edge_types if t != "RT")
        self.attributes = sorted(
            (name, kind)
            for name, kind in self.vocabulary.attributes.items()
            if kind in ("bool", "int", "float", "string", "float_vector")
        )
        self.serial = 0

    # ------------------------------------------------------------------ values
    def value(self, kind: str) -> Any:
        p = self.pick
        if kind == "bool":
            return p.choice([True, False])
        if kind == "int":
            return p.integer(-1000, 1000)
        if kind == "float":
            return p.real(-1e3, 1e3)
        if kind == "string":
            return p.choice(["", "a", "Blue", "ñandú", "x" * 40])
        return [p.real(-10, 10) for _ in range(p.integer(0, 4))]

    def attrs(self) -> dict[str, Any]:
        return {
            name: self.value(kind)
            for name, kind in (
                self.pick.choice(self.attributes) for _ in range(self.pick.integer(0, 2))
            )
        }

    def pose(self) -> dict[str, Any]:
        p = self.pick
        return {
            "translation": [p.real(-5, 5) for _ in range(3)],
            "rotation_euler_xyz": [p.real(-math.pi, math.pi) for _ in range(3)],
        }

    # ------------------------------------------------------------------ drawing
    def transaction(self, graph: Graph, mistake: bool = False) -> dict[str, Any]:
        """1 to 3 valid ops; with ``mistake``, one of them (at a drawn place) breaks a rule."""
        text = json.dumps(dsr_json.to_json(graph, "snapshot"))  # a copy that shares no dict
        scratch, _ = dsr_json.snapshot_from_json(json.loads(text), trusted=True)
        count = self.pick.integer(1, 3)
        wrong_at = self.pick.integer(0, count - 1) if mistake else -1
        ops = []
        for i in range(count):
            names = [n.name for n in scratch.nodes()]
            if i == wrong_at and len(names) >= 2:
                ops.append(
                    self.mistake(
                        scratch,
                        names,
                        [n for n in names if scratch.is_geometric(n)],
                        self.pick.choice(names),
                    )
                )
                continue
            if i == wrong_at:
                ops.append({"op": "delete_node", "node": "missing-node"})
                continue
            op = self.op(scratch)
            apply_ops(scratch, [op])  # valid by construction: a failure here is a bug of ours
            ops.append(op)
        return {"ops": ops}

    def op(self, graph: Graph) -> dict[str, Any]:
        total = sum(w for _, w in KINDS)
        roll, kind = self.pick.integer(1, total), KINDS[-1][0]
        for name, weight in KINDS:
            roll -= weight
            if roll <= 0:
                kind = name
                break
        names = [n.name for n in graph.nodes()]
        if len(names) < 2 or kind == "insert_node":
            self.serial += 1
            return {
                "op": "insert_node",
                "name": f"n{self.serial}",
                "type": self.pick.choice(self.node_types),
                "attrs": self.attrs(),
            }
        geometric = [n for n in names if graph.is_geometric(n)]
        plain = [n for n in names if not graph.is_geometric(n)]
        a, b = self.pick.choice(names), self.pick.choice(names)
        if kind == "insert_edge":
            free = self._free_edge(graph, names, a, b, self.pick.choice(self.edge_types))
            if free is not None:
                return {
                    "op": "insert_edge",
                    "from": free[0],
                    "to": free[1],
                    "type": free[2],
                    "attrs": self.attrs(),
                }
        if kind == "insert_rt" and plain:
            # the newest geometric nodes are the deepest: hang the child under one of them
            parent = self.pick.choice(geometric[-4:]) if geometric else self.pick.choice(names)
            child = self.pick.choice([n for n in plain if n != parent] or plain)
            return {
                "op": "insert_edge",
                "from": parent,
                "to": child,
                "type": "RT",
                "rt": self.pose(),
            }
        symbolic = [e for e in graph.edges() if e.type != "RT"]
        rt_edges = [e for e in graph.edges() if e.type == "RT"]
        if kind == "set_rt" and rt_edges:
            e = self.pick.choice(rt_edges)
            return {
                "op": "set_rt",
                "from": graph.node(e.src).name,
                "to": graph.node(e.dst).name,
                "rt": self.pose(),
            }
        if kind in ("set_edge_attrs", "delete_edge") and symbolic:
            e = self.pick.choice(symbolic)
            op = {
                "op": kind,
                "from": graph.node(e.src).name,
                "to": graph.node(e.dst).name,
                "type": e.type,
            }
            return dict(op, attrs=self.attrs()) if kind == "set_edge_attrs" else op
        if kind == "delete_leaf":
            leaves = [n for n in names if not graph.rt_children(n)]
            return {"op": "delete_node", "node": self.pick.choice(leaves)}
        if kind == "remove_node_attrs":
            with_attrs = [n for n in graph.nodes() if n.attrs]
            if with_attrs:
                node = self.pick.choice(with_attrs)
                return {
                    "op": "remove_node_attrs",
                    "node": node.name,
                    "names": [self.pick.choice(sorted(node.attrs))],
                }
        return {"op": "set_node_attrs", "node": a, "attrs": self.attrs()}

    def _free_edge(self, graph: Graph, names: list[str], a: str, b: str, kind: str):
        """The first (from, to, type) from the drawn one on that is not an edge yet, if any."""
        types = (
            self.edge_types[self.edge_types.index(kind) :]
            + self.edge_types[: self.edge_types.index(kind)]
        )
        start = names.index(b)
        for t in types:
            for k in range(len(names)):
                other = names[(start + k) % len(names)]
                if other != a and graph.edge(a, other, t) is None:
                    return a, other, t
        return None

    def mistake(
        self, graph: Graph, names: list[str], geometric: list[str], a: str
    ) -> dict[str, Any]:
        which = self.pick.choice(MISTAKES)
        if which == "self_loop":
            return {
                "op": "insert_edge",
                "from": a,
                "to": a,
                "type": self.pick.choice(self.edge_types),
            }
        if which == "rt_cycle" and len(geometric) >= 2:
            deep = geometric[-1]
            root = graph.rt_root()
            if root is not None and deep != root.name:
                return {
                    "op": "insert_edge",
                    "from": deep,
                    "to": root.name,
                    "type": "RT",
                    "rt": self.pose(),
                }
        if which == "second_parent" and geometric:
            child = self.pick.choice(geometric)
            if graph.rt_parent(child) is not None:
                other = next(
                    (n for n in names if n != child and n != graph.rt_parent(child).name), None
                )
                if other is not None:
                    return {
                        "op": "insert_edge",
                        "from": other,
                        "to": child,
                        "type": "RT",
                        "rt": self.pose(),
                    }
        if which == "orphan_subtree":
            inner = [n for n in geometric if graph.rt_children(n)]
            if inner:
                return {"op": "delete_node", "node": self.pick.choice(inner)}
        if which == "unknown_node_type":
            return {"op": "insert_node", "name": "alien", "type": "no_such_type"}
        if which == "unknown_edge_type":
            return {
                "op": "insert_edge",
                "from": a,
                "to": names[0] if a != names[0] else names[1],
                "type": "bogus",
            }
        if which == "not_rigid" and geometric:
            child = next((n for n in geometric if graph.rt_parent(n) is not None), None)
            if child is not None:
                return {
                    "op": "set_rt",
                    "from": graph.rt_parent(child).name,
                    "to": child,
                    "rt": NOT_RIGID,
                }
        if which == "unknown_attribute":
            return {"op": "set_node_attrs", "node": a, "attrs": {"no_such_attribute": 1}}
        if which == "wrong_attribute_type":
            name = next(n for n, kind in self.attributes if kind == "float_vector")
            return {"op": "set_node_attrs", "node": a, "attrs": {name: "not a vector"}}
        return {"op": "delete_node", "node": "missing-node"}


def rt_depth(graph: Graph) -> int:
    """Edges on the longest path from the RT root down."""
    return (
        max(
            (
                len(graph.chain(graph.rt_root().name, n.name)) - 1
                for n in graph.nodes()
                if graph.is_geometric(n.id)
            ),
            default=0,
        )
        if graph.rt_root() is not None
        else 0
    )
