"""CORTEX's signals: ``signals.connect(g, signals.UPDATE_NODE, fn)``, and the pure translation of
the DSR's deltas into the calls CORTEX makes (python_api.cpp's handler signatures):

    UPDATE_NODE(id, type)              UPDATE_NODE_ATTR(id, [names])
    UPDATE_EDGE(from, to, type)        UPDATE_EDGE_ATTR(from, to, type, [names])
    DELETE_EDGE(from, to, type)        DELETE_NODE(id)
    DELETE_NODE_OBJ(Node)              DELETE_EDGE_OBJ(Edge)

Every applied delta is translated, whoever wrote it. A deleted node's edges go first (each a
DELETE_EDGE), then the node. ``Mirror`` keeps the graph as it was before each delta, which is
what a deletion's ids and objects come from.
"""

from __future__ import annotations

import enum
from collections.abc import Callable, Iterator
from typing import Any

from dsr_graph.formats import dsr_json
from dsr_graph.model.graph import Graph
from dsr_graph.model.transaction import apply_op
from pydsr import convert


class signal_type(enum.IntEnum):  # noqa: N801 (CORTEX's name)
    UPDATE_NODE = 0
    UPDATE_NODE_ATTR = 1
    UPDATE_EDGE = 2
    UPDATE_EDGE_ATTR = 3
    DELETE_EDGE = 4
    DELETE_NODE = 5
    DELETE_NODE_OBJ = 6
    DELETE_EDGE_OBJ = 7


UPDATE_NODE = signal_type.UPDATE_NODE
UPDATE_NODE_ATTR = signal_type.UPDATE_NODE_ATTR
UPDATE_EDGE = signal_type.UPDATE_EDGE
UPDATE_EDGE_ATTR = signal_type.UPDATE_EDGE_ATTR
DELETE_EDGE = signal_type.DELETE_EDGE
DELETE_NODE = signal_type.DELETE_NODE
DELETE_NODE_OBJ = signal_type.DELETE_NODE_OBJ
DELETE_EDGE_OBJ = signal_type.DELETE_EDGE_OBJ

Event = tuple[signal_type, tuple[Any, ...]]


def connect(graph: Any, kind: signal_type, fn: Callable[..., Any]) -> None:
    """Call ``fn`` with the signal's arguments for every change of ``graph`` (a ``DSRGraph``)."""
    if not callable(fn):
        raise TypeError(f"signals.connect: {fn!r} is not callable")
    graph._connect(signal_type(kind), fn)


class Mirror:
    """The graph as the signals last saw it; ``advance`` applies a delta and tells its events."""

    def __init__(self, graph: Graph):
        self.graph = _copy(graph)

    def advance(self, delta: dict[str, Any]) -> list[Event]:
        events: list[Event] = []
        with self.graph.atomic():
            for op in delta.get("ops", []):
                events.extend(self._before(op))
                apply_op(self.graph, op)
                events.extend(self._after(op))
        return events

    def resync(self, graph: Graph) -> list[Event]:
        """After a snapshot: what differs from the graph seen before, as signals."""
        old, self.graph = self.graph, _copy(graph)
        new = self.graph
        events: list[Event] = []
        old_edges = {e.key: e for e in old.edges()}
        new_edges = {e.key: e for e in new.edges()}
        for key, edge in old_edges.items():
            if key not in new_edges:
                events += _edge_deleted(old, edge)
        for node in old.nodes():
            if node.id not in new or new.node(node.id).name != node.name:
                events += _node_deleted(old, node.id, with_edges=False)
        for node in new.nodes():
            before = old.find(node.id)
            if before is None or before.name != node.name:
                events.append((UPDATE_NODE, (node.id, node.type)))
            elif before.attrs != node.attrs:
                names = sorted(set(before.attrs) | set(node.attrs))
                events.append((UPDATE_NODE_ATTR, (node.id, names)))
        for key, edge in new_edges.items():
            before = old_edges.get(key)
            if before is None:
                events.append((UPDATE_EDGE, key))
            elif before.attrs != edge.attrs:
                names = sorted(set(before.attrs) | set(edge.attrs))
                events.append((UPDATE_EDGE_ATTR, (*key, names)))
            elif edge.rt is not None and not (before.rt == edge.rt).all():
                events.append((UPDATE_EDGE, key))
        return events

    # -- one op ------------------------------------------------------------------------------
    def _before(self, op: dict[str, Any]) -> Iterator[Event]:
        g = self.graph
        kind = op["op"]
        if kind == "delete_node":
            node = g.find(op["node"])
            if node is not None:
                yield from _node_deleted(g, node.id, with_edges=True)
        elif kind == "delete_edge":
            edge = g.edge(op["from"], op["to"], op["type"])
            if edge is not None:
                yield from _edge_deleted(g, edge)

    def _after(self, op: dict[str, Any]) -> Iterator[Event]:
        g = self.graph
        kind = op["op"]
        if kind == "insert_node":
            node = g.node(op["name"])
            yield UPDATE_NODE, (node.id, node.type)
        elif kind in ("set_node_attrs", "remove_node_attrs"):
            names = list(op["attrs"]) if kind == "set_node_attrs" else list(op["names"])
            yield UPDATE_NODE_ATTR, (g.node(op["node"]).id, names)
        elif kind in ("insert_edge", "set_rt"):
            yield UPDATE_EDGE, _ids(g, op, op.get("type", "RT"))
        elif kind in ("set_edge_attrs", "remove_edge_attrs"):
            names = list(op["attrs"]) if kind == "set_edge_attrs" else list(op["names"])
            yield UPDATE_EDGE_ATTR, (*_ids(g, op, op["type"]), names)


def _ids(g: Graph, op: dict[str, Any], type: str) -> tuple[int, int, str]:
    return g.node(op["from"]).id, g.node(op["to"]).id, type


def _edge_deleted(g: Graph, edge) -> list[Event]:
    return [
        (DELETE_EDGE, edge.key),
        (DELETE_EDGE_OBJ, (convert.edge_of(g, edge),)),
    ]


def _node_deleted(g: Graph, node_id: int, with_edges: bool) -> list[Event]:
    events: list[Event] = []
    if with_edges:
        for edge in g.out_edges(node_id) + g.in_edges(node_id):
            events += _edge_deleted(g, edge)
    events.append((DELETE_NODE, (node_id,)))
    events.append((DELETE_NODE_OBJ, (convert.node_of(g, g.node(node_id)),)))
    return events


def _copy(graph: Graph) -> Graph:
    # the document shares the graph's attribute dicts: each is copied (the values themselves
    # are replaced by changes, never changed in place; binary ones are read-only)
    doc = dsr_json.to_json(graph, kind="snapshot", seq=0)
    for item in doc["nodes"] + doc["edges"]:
        item["attrs"] = dict(item["attrs"])
        if "provenance" in item:
            item["provenance"] = dict(item["provenance"])
    copy, _ = dsr_json.snapshot_from_json(doc, graph.vocabulary, trusted=True)
    copy.trusted_rt = True
    return copy
