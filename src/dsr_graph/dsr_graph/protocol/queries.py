"""Read-only answers about a graph, shaped for the server's services (pure; no ROS)."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from dsr_graph.exceptions import LookupFailed
from dsr_graph.model import provenance, rigid
from dsr_graph.model.binary import BYTES, ELEMENT_OF, BlobRef
from dsr_graph.model.graph import Edge, Graph
from dsr_graph.model.vocabulary import RT


@dataclass
class AttributeAnswer:
    found: bool
    value: Any = None
    value_type: str = ""
    version: int = 0
    error: str = ""


def read_attribute(
    graph: Graph, node: str, attribute: str, edge_to: str = "", edge_type: str = ""
) -> AttributeAnswer:
    """The attribute of node ``node``, or of its edge to ``edge_to`` of type ``edge_type``.
    On an RT edge the pseudo-attribute ``rt`` is the 4x4 transform."""
    source = graph.find(node)
    if source is None:
        return AttributeAnswer(False, error=f"no node {node!r}")
    if bool(edge_to) != bool(edge_type):
        return AttributeAnswer(
            False, error="give both edge_to and edge_type to read an edge attribute, or neither"
        )
    holder: Any = source
    label = f"node {node!r}"
    if edge_to:
        if graph.find(edge_to) is None:
            return AttributeAnswer(False, error=f"no node {edge_to!r}")
        holder = graph.edge(node, edge_to, edge_type)
        label = f"edge {node!r}->{edge_to!r} ({edge_type})"
        if holder is None:
            return AttributeAnswer(False, error=f"no {label}")
        if edge_type == RT and attribute == "rt":
            return AttributeAnswer(True, holder.rt.tolist(), "float_matrix", holder.version)
    if attribute not in holder.attrs:
        return AttributeAnswer(
            False, version=holder.version, error=f"{label} has no attribute {attribute!r}"
        )
    return AttributeAnswer(
        True,
        holder.attrs[attribute],
        graph.vocabulary.attribute_type(attribute) or "",
        holder.version,
    )


def edge_json(graph: Graph, edge: Edge) -> dict[str, Any]:
    doc: dict[str, Any] = {
        "from": graph.node(edge.src).name,
        "to": graph.node(edge.dst).name,
        "type": edge.type,
        "attrs": edge.attrs,
        "version": edge.version,
    }
    if edge.rt is not None:
        doc["rt"] = rigid.to_json(edge.rt)
    if edge.prov:  # who wrote each attribute (and the transform, "$rt"), and when
        doc["provenance"] = provenance.shown(edge.prov)
    return doc


def node_json(graph: Graph, name: str) -> dict[str, Any] | None:
    node = graph.find(name)
    if node is None:
        return None
    key = lambda e: (e.src, e.dst, e.type)  # noqa: E731 - a stable order for readers and tests
    doc = {
        "id": node.id,
        "name": node.name,
        "type": node.type,
        "attrs": node.attrs,
        "version": node.version,
        "out": [edge_json(graph, e) for e in sorted(graph.out_edges(node.id), key=key)],
        "in": [edge_json(graph, e) for e in sorted(graph.in_edges(node.id), key=key)],
    }
    if node.prov:
        doc["provenance"] = provenance.shown(node.prov)
    return doc


def transform(graph: Graph, frm: str, to: str, at: float = 0.0) -> np.ndarray:
    """``to``'s pose in ``frm``'s frame, now (``at`` 0) or at time ``at`` from the RT history;
    ``LookupFailed`` (``OutsideHistory``) says why not."""
    if isinstance(at, bool) or not isinstance(at, (int, float)) or not math.isfinite(at):
        raise LookupFailed(f"at must be seconds since the epoch (0: now), got {at!r}")
    return graph.transform(frm, to) if at == 0 else graph.transform_at(frm, to, float(at))


@dataclass
class BinaryAnswer:
    found: bool
    dtype: str = ""
    shape: tuple[int, ...] = ()
    data: bytes = b""
    error: str = ""


def read_binary(graph: Graph, node: str, attribute: str) -> BinaryAnswer:
    """The bytes of a node's binary value (bytes, or an array: its element type and shape)."""
    holder = graph.find(node)
    if holder is None:
        return BinaryAnswer(False, error=f"no node {node!r}")
    if attribute not in holder.attrs:
        return BinaryAnswer(False, error=f"node {node!r} has no attribute {attribute!r}")
    value = holder.attrs[attribute]
    if isinstance(value, bytes):
        return BinaryAnswer(True, BYTES, (), value)
    if isinstance(value, np.ndarray):
        return BinaryAnswer(True, ELEMENT_OF[value.dtype], value.shape, value.tobytes())
    if isinstance(value, BlobRef):
        where = f"dsr/get_blob/{value.at}" if value.at else "a replica that was sent them"
        return BinaryAnswer(
            False,
            error=f"node {node!r}: the bytes of {attribute!r} ({value.digest}) are not held here: "
            f"ask {where}",
        )
    return BinaryAnswer(
        False, error=f"node {node!r}: {attribute!r} is not a binary value (dsr/get_attribute)"
    )
