"""Between the DSR's graph and pydsr's elements (pure). CORTEX holds RT translations in
millimetres and the DSR in metres: they are converted here, and nowhere else. An RT edge shows
its transform as CORTEX's attributes ``rt_translation`` (mm) and ``rt_rotation_euler_xyz``
(radians, float32 as CORTEX keeps them); written back, they become the edge's transform.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from dsr_graph.formats.units import PER_METRE
from dsr_graph.model import rigid
from dsr_graph.model.binary import ARRAYS, BYTES, BlobRef
from dsr_graph.model.graph import Edge as GraphEdge
from dsr_graph.model.graph import Graph
from dsr_graph.model.graph import Node as GraphNode
from dsr_graph.model.provenance import RT_KEY
from dsr_graph.model.vocabulary import RT
from pydsr.elements import Attribute, AttributeMap, Edge, Node, agent_number

MM = PER_METRE["mm"]
RT_TRANSLATION = "rt_translation"
RT_ROTATION = "rt_rotation_euler_xyz"
RT_ATTRS = (RT_TRANSLATION, RT_ROTATION)


def attribute_of(value: Any, stamp: tuple[float, str] | None = None) -> Attribute:
    """A graph value as CORTEX returns it (float vectors as float32 arrays, byte vectors as
    uint8, images as the arrays they are), with its provenance: the time (ns) and the agent of
    its last write; 0 and 0 if unknown."""
    if isinstance(value, BlobRef):  # bytes this replica was not sent (camera_api fetches them)
        value = np.zeros(0, dtype=np.uint8)
    return _stamped(Attribute(value, 0, 0), stamp)


def _read(attrs: AttributeMap, values: dict[str, Any], prov: dict) -> None:
    """The graph's values into a map, typed by their names where they fit (a value the graph
    holds always fits its vocabulary type; a CORTEX shape it does not is left untyped)."""
    for name, value in values.items():
        attribute = attribute_of(value, prov.get(name))
        try:
            attrs[name] = attribute
        except TypeError:
            dict.__setitem__(attrs, name, attribute)


def _stamped(attribute: Attribute, stamp: tuple[float, str] | None) -> Attribute:
    if stamp is not None:
        when, agent = stamp
        attribute._timestamp = round(when * 1e9)
        attribute._agent_id = agent_number(agent)
        attribute._agent_name = agent
    return attribute


def node_of(graph: Graph, node: GraphNode) -> Node:
    out = Node._of(node.id, node.type, node.name)
    _read(out.attrs, node.attrs, node.prov)
    for edge in graph.out_edges(node.id):
        out.edges[(edge.dst, edge.type)] = edge_of(graph, edge)
    return out


def edge_of(graph: Graph, edge: GraphEdge) -> Edge:
    out = Edge(edge.dst, edge.src, edge.type, 0)
    _read(out.attrs, edge.attrs, edge.prov)
    if edge.rt is not None:
        moved = edge.prov.get(RT_KEY)
        translation = np.asarray(edge.rt[:3, 3] * MM, dtype=np.float32)
        rotation = np.asarray(rigid.euler_xyz(edge.rt), dtype=np.float32)
        out.attrs[RT_TRANSLATION] = _stamped(Attribute(translation, 0, 0), moved)
        out.attrs[RT_ROTATION] = _stamped(Attribute(rotation, 0, 0), moved)
    return out


def rt_of(translation_mm: Any, rotation_euler_xyz: Any) -> dict[str, Any]:
    """CORTEX's pose (mm, radians) as the DSR's ``rt`` (metres)."""
    translation = [float(v) / MM for v in np.asarray(translation_mm, dtype=float).ravel()]
    rotation = [float(v) for v in np.asarray(rotation_euler_xyz, dtype=float).ravel()]
    return {"translation": translation, "rotation_euler_xyz": rotation}


def matrix_mm(matrix: np.ndarray) -> np.ndarray:
    """A DSR transform (metres) as CORTEX's 4x4 (mm)."""
    out = np.array(matrix, dtype=float)
    out[:3, 3] *= MM
    return out


def graph_value(graph: Graph, name: str, attribute: Attribute) -> Any:
    """An attribute's value as the graph's vocabulary types it (JSON-able, or bytes)."""
    value = attribute.value
    if isinstance(value, np.ndarray):
        type_name = graph.vocabulary.attribute_type(name)
        if type_name == BYTES:
            return value.astype(np.uint8).tobytes()
        if type_name in ARRAYS:  # CORTEX's vectors are flat: an array of one dimension
            return np.ascontiguousarray(value, dtype=ARRAYS[type_name][1])
        return [int(v) for v in value] if value.dtype.kind in "ui" else [float(v) for v in value]
    return value


def attr_changes(
    graph: Graph, current: dict[str, Any], wanted: dict[str, Attribute], rt: bool = False
) -> tuple[dict[str, Any], list[str]]:
    """The sets and removals that turn ``current`` (a graph element's attrs) into ``wanted``;
    an attribute read and handed back unchanged is not written again. ``rt``: an RT edge, whose
    ``rt_translation`` and ``rt_rotation_euler_xyz`` are its transform, not attributes."""
    skipped = RT_ATTRS if rt else ()
    sets = {}
    for name, attribute in wanted.items():
        if name in skipped:
            continue
        if name in current and _same(_shown(name, current[name]), attribute.value):
            continue
        sets[name] = graph_value(graph, name, attribute)
    removes = [name for name in current if name not in wanted and name not in skipped]
    return sets, removes


def _shown(name: str, value: Any) -> Any:
    """A graph value as a program reading it sees it (typed by its name where it fits)."""
    attribute = attribute_of(value)
    try:
        attribute._bind(name)
    except TypeError:
        pass
    return attribute.value


def wanted_rt(edge: Edge, current: GraphEdge | None = None) -> dict[str, Any] | None:
    """The transform an edge's CORTEX attributes give, when it has both; None also when they
    are those ``current`` shows (read and handed back unchanged)."""
    if edge.type != RT or not all(k in edge.attrs for k in RT_ATTRS):
        return None
    if current is not None and current.rt is not None:
        shown = {
            RT_TRANSLATION: current.rt[:3, 3] * MM,
            RT_ROTATION: rigid.euler_xyz(current.rt),
        }
        if all(
            _same(np.asarray(shown[k], dtype=np.float32), edge.attrs[k].value) for k in RT_ATTRS
        ):
            return None
    return rt_of(edge.attrs[RT_TRANSLATION].value, edge.attrs[RT_ROTATION].value)


def _same(a: Any, b: Any) -> bool:
    if isinstance(a, np.ndarray) or isinstance(b, np.ndarray):
        return np.shape(a) == np.shape(b) and bool(np.all(np.asarray(a) == np.asarray(b)))
    return type(a) is type(b) and a == b
