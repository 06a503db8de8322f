"""The DSR drawn for ROS tools (pure): where each node and edge goes on ``dsr/markers``, so that
RViz or Foxglove show the graph without our viewer. Geometric nodes stand at their pose in the
RT root's frame; a symbolic node stands above the geometric node it is linked to (the person's
``answer`` above the person), or, linked to none, in a row above the scene. Lengths are metres,
as in the DSR (units.py) and in ROS tools (REP 103).
"""

from __future__ import annotations

from dataclasses import dataclass

from dsr_graph.exceptions import LookupFailed
from dsr_graph.model.graph import Graph
from dsr_graph.model.vocabulary import RT

SYMBOL_RISE = 0.25  # metres between a geometric node and each symbol stacked above it
ROW_GAP = 0.5  # metres between unanchored symbols, and between the scene's top and their row

Point = tuple[float, float, float]


@dataclass(frozen=True)
class NodeMark:
    name: str
    type: str
    position: Point
    geometric: bool


@dataclass(frozen=True)
class EdgeMark:
    src: str
    dst: str
    type: str
    start: Point
    end: Point


@dataclass(frozen=True)
class GraphDrawing:
    frame: str  # the RT root's name: the fixed frame to choose in RViz
    nodes: list[NodeMark]
    edges: list[EdgeMark]


def _geometric_positions(graph: Graph, root: str) -> dict[str, Point]:
    positions = {}
    for node in graph.nodes():
        if node.name == root or not graph.is_geometric(node.name):
            continue
        try:
            x, y, z = graph.transform(root, node.name)[:3, 3]
        except LookupFailed:  # a second RT tree (only in a world that breaks the rules)
            continue
        positions[node.name] = (float(x), float(y), float(z))
    positions[root] = (0.0, 0.0, 0.0)
    return positions


def drawing(graph: Graph) -> GraphDrawing:
    root_node = graph.rt_root()
    root = root_node.name if root_node is not None else "dsr"
    positions = _geometric_positions(graph, root) if root_node is not None else {}
    geometric = set(positions)
    neighbours: dict[str, set[str]] = {}
    for e in graph.edges():
        if e.type != RT:
            src, dst = graph.node(e.src).name, graph.node(e.dst).name
            neighbours.setdefault(src, set()).add(dst)
            neighbours.setdefault(dst, set()).add(src)
    symbols = sorted(n.name for n in graph.nodes() if n.name not in geometric)
    stacked: dict[str, int] = {}  # anchor -> symbols stacked on it so far
    unanchored = []
    for name in symbols:
        anchor = min((n for n in neighbours.get(name, ()) if n in geometric), default=None)
        if anchor is None:
            unanchored.append(name)
            continue
        stacked[anchor] = stacked.get(anchor, 0) + 1
        x, y, z = positions[anchor]
        positions[name] = (x, y, z + SYMBOL_RISE * stacked[anchor])
    top = max((p[2] for p in positions.values()), default=0.0) + ROW_GAP
    for k, name in enumerate(unanchored):
        positions[name] = ((k - (len(unanchored) - 1) / 2) * ROW_GAP, 0.0, top)
    nodes = [
        NodeMark(n.name, n.type, positions[n.name], n.name in geometric)
        for n in sorted(graph.nodes(), key=lambda n: n.name)
    ]
    edges = [
        EdgeMark(
            graph.node(e.src).name,
            graph.node(e.dst).name,
            e.type,
            positions[graph.node(e.src).name],
            positions[graph.node(e.dst).name],
        )
        for e in graph.edges()
    ]
    return GraphDrawing(root, nodes, sorted(edges, key=lambda e: (e.src, e.dst, e.type)))
