"""Volatile changes: sensor data that is broadcast without waiting for the disk (pure).

A change is volatile when every operation only sets values the vocabulary declares volatile
(attributes with ``"volatile": true``; the pose of a node whose type has ``"volatile_pose":
true``, as ``set_rt`` moves it) and it grants or ends no claim. The server numbers it after the
durable change it follows, without taking a sequence number of its own: its delta carries that
durable ``seq`` and a ``volatile`` count. So a crash, which loses the volatile changes not yet in
a snapshot, never moves a replica's seq beyond the restarted server's durable one; and a
replica that is not at exactly that ``seq`` (behind, or resynchronising) skips it and takes the
next one. Every other change keeps the server's guarantee: durable before its writer hears it
was accepted (protocol/acceptance.py).
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from typing import Any

from dsr_graph.model.graph import Graph

VOLATILE = "volatile"  # the delta key: the server's count of volatile deltas


def is_volatile(delta: Mapping[str, Any]) -> bool:
    return VOLATILE in delta


def follows(delta: Mapping[str, Any], seq: int) -> bool:
    """Whether ``delta`` applies to a graph at ``seq``: a durable delta to seq - 1 of its own, a
    volatile one to the very seq it carries."""
    return delta["seq"] == (seq if is_volatile(delta) else seq + 1)


def only_volatile(graph: Graph, ops: Iterable[Mapping[str, Any]]) -> bool:
    """Whether canonical ``ops`` (applied to ``graph``) only set volatile values."""
    vocabulary = graph.vocabulary
    any_op = False
    for op in ops:
        any_op = True
        kind = op["op"]
        if kind in ("set_node_attrs", "set_edge_attrs"):
            if not set(op["attrs"]) <= vocabulary.volatile:
                return False
        elif kind == "set_rt":
            child = graph.find(op["to"])
            if child is None or child.type not in vocabulary.volatile_poses:
                return False
        else:
            return False
    return any_op


def without_absent_volatile(graph: Graph, op: Mapping[str, Any]) -> Mapping[str, Any]:
    """A journalled removal of attributes, less the volatile ones the graph does not hold: they
    were set by volatile changes a crash lost, and their removal replays as nothing."""
    if op["op"] == "remove_node_attrs":
        element = graph.find(op["node"])
    elif op["op"] == "remove_edge_attrs":
        element = graph.edge(op["from"], op["to"], op["type"])
    else:
        return op
    if element is None:
        return op
    absent = {n for n in op["names"] if n in graph.vocabulary.volatile and n not in element.attrs}
    return {**op, "names": [n for n in op["names"] if n not in absent]} if absent else op
