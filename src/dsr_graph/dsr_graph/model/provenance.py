"""Who wrote each attribute, and when: the time and the agent of the delta that last set it
(CORTEX keeps both on every attribute; a clinician's audit needs them). Pure.

The server stamps what it accepts with the delta's own ``stamp`` and ``agent``, so a delta carries
nothing more on the wire and every replica that applies it stamps the same. Snapshots and world
files carry an element's stamps as ``"provenance": {name: [time, agent]}`` (optional on read).
An RT edge's transform is stamped under ``RT_KEY``. Each element keeps ``prov``: name ->
(time, agent); one tuple per delta is shared by every attribute it wrote.
"""

from __future__ import annotations

import math
import sys
from collections.abc import Iterable, Mapping
from typing import Any

from dsr_graph.exceptions import FormatError
from dsr_graph.model import rt_history
from dsr_graph.model.graph import Graph
from dsr_graph.model.transaction import apply_ops

RT_KEY = "$rt"  # an RT edge's transform ("$": never an attribute's name)
Stamp = tuple[float, str]


def stamp(graph: Graph, ops: Iterable[Mapping[str, Any]], when: Any, agent: Any) -> None:
    """Stamp what ``ops`` (canonical, already applied to ``graph``) wrote."""
    if isinstance(when, bool) or not isinstance(when, (int, float)) or not isinstance(agent, str):
        return  # a delta without them (written before provenance): nothing to say
    mark: Stamp = (float(when), sys.intern(agent))
    for op in ops:
        kind = op["op"]
        if kind in ("insert_node", "set_node_attrs", "remove_node_attrs"):
            node = graph.find(op["name"] if kind == "insert_node" else op["node"])
            if node is not None:
                _mark(
                    node.prov,
                    op,
                    kind == "remove_node_attrs",
                    mark,
                    fresh=kind == "insert_node",
                )
        elif kind in ("insert_edge", "set_edge_attrs", "remove_edge_attrs", "set_rt"):
            edge = graph.edge(op["from"], op["to"], op.get("type", "RT"))  # None if gone
            if edge is None:
                continue
            if kind == "set_rt":
                edge.prov[RT_KEY] = mark
                continue
            _mark(edge.prov, op, kind == "remove_edge_attrs", mark, fresh=kind == "insert_edge")
            if kind == "insert_edge" and edge.rt is not None:
                edge.prov[RT_KEY] = mark


def _mark(prov: dict, op: Mapping[str, Any], removed: bool, mark: Stamp, fresh: bool) -> None:
    if fresh:
        prov.clear()
    if removed:
        for name in op["names"]:
            prov.pop(name, None)
    else:
        for name in op.get("attrs") or ():
            prov[name] = mark


def apply_delta(graph: Graph, delta: Mapping[str, Any], ops: list | None = None) -> None:
    """Apply a delta the server accepted (a replica, a replay): stamp what it wrote, and keep
    the transforms it wrote in the RT history, at the delta's time."""
    ops = delta["ops"] if ops is None else ops
    apply_ops(graph, ops)
    stamped(graph, ops, delta.get("stamp"), delta.get("agent"))


def stamped(graph: Graph, ops: list, when: Any, agent: Any) -> None:
    """What a delta's ``ops`` (applied) wrote, stamped at ``when`` by ``agent``: provenance and
    the RT history."""
    stamp(graph, ops, when, agent)
    rt_history.remember(graph, ops, when)


def read(value: Any, names: Iterable[str], element: str) -> dict[str, Stamp]:
    """An element's ``provenance`` from a document: stamps of attributes it has (or of its
    transform), each ``[time, agent]``; ``FormatError`` naming what is wrong."""
    if not isinstance(value, dict):
        raise FormatError(f'{element}: "provenance" must be an object, got {value!r}')
    known = set(names) | {RT_KEY}
    out: dict[str, Stamp] = {}
    for name, item in value.items():
        if name not in known:
            raise FormatError(f"{element}: provenance of {name!r}, which it does not have")
        if (
            not isinstance(item, (list, tuple))
            or len(item) != 2
            or isinstance(item[0], bool)
            or not isinstance(item[0], (int, float))
            or not math.isfinite(item[0])
            or not isinstance(item[1], str)
        ):
            raise FormatError(
                f"{element}: provenance of {name!r} must be [time, agent], got {item!r}"
            )
        out[name] = (float(item[0]), sys.intern(item[1]))
    return out


def shown(prov: Mapping[str, Stamp]) -> dict[str, dict[str, Any]]:
    """For people (``dsr get --provenance``, the viewer): name -> {"time", "agent"}."""
    return {name: {"time": t, "agent": a} for name, (t, a) in sorted(prov.items())}
