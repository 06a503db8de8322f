"""The graph drawing (protocol/graph_markers.py) as a ``visualization_msgs/MarkerArray`` for
``dsr/markers``: a sphere and a label per node (geometric nodes blue, symbolic ones orange), a
line and a label per edge (RT edges thin and grey). Each array starts with DELETEALL, so a node
or edge that is gone disappears from RViz and Foxglove."""

from __future__ import annotations

from builtin_interfaces.msg import Time
from geometry_msgs.msg import Point
from std_msgs.msg import ColorRGBA
from visualization_msgs.msg import Marker, MarkerArray

from dsr_graph.model.vocabulary import RT
from dsr_graph.protocol.graph_markers import GraphDrawing

GEOMETRIC = ColorRGBA(r=0.2, g=0.45, b=0.9, a=1.0)
SYMBOLIC = ColorRGBA(r=0.95, g=0.55, b=0.1, a=1.0)
EDGE = ColorRGBA(r=0.1, g=0.1, b=0.1, a=0.9)
RT_EDGE = ColorRGBA(r=0.6, g=0.6, b=0.6, a=0.6)
TEXT = ColorRGBA(r=1.0, g=1.0, b=1.0, a=1.0)


def _marker(frame: str, stamp: Time, ns: str, ident: int, kind: int) -> Marker:
    m = Marker()
    m.header.frame_id = frame
    m.header.stamp = stamp
    m.ns, m.id, m.type, m.action = ns, ident, kind, Marker.ADD
    m.pose.orientation.w = 1.0
    return m


def _point(p: tuple[float, float, float]) -> Point:
    return Point(x=p[0], y=p[1], z=p[2])


def marker_array(drawing: GraphDrawing, stamp: Time) -> MarkerArray:
    clear = Marker()
    clear.action = Marker.DELETEALL
    markers = [clear]
    frame = drawing.frame
    for k, node in enumerate(drawing.nodes):
        sphere = _marker(frame, stamp, "dsr_nodes", k, Marker.SPHERE)
        sphere.pose.position = _point(node.position)
        sphere.scale.x = sphere.scale.y = sphere.scale.z = 0.08
        sphere.color = GEOMETRIC if node.geometric else SYMBOLIC
        label = _marker(frame, stamp, "dsr_node_labels", k, Marker.TEXT_VIEW_FACING)
        x, y, z = node.position
        label.pose.position = _point((x, y, z + 0.08))
        label.scale.z = 0.06
        label.color = TEXT
        label.text = f"{node.name} ({node.type})"
        markers += [sphere, label]
    for k, edge in enumerate(drawing.edges):
        line = _marker(frame, stamp, "dsr_edges", k, Marker.LINE_LIST)
        line.points = [_point(edge.start), _point(edge.end)]
        line.scale.x = 0.005 if edge.type == RT else 0.012
        line.color = RT_EDGE if edge.type == RT else EDGE
        markers.append(line)
        if edge.type != RT:
            label = _marker(frame, stamp, "dsr_edge_labels", k, Marker.TEXT_VIEW_FACING)
            label.pose.position = _point(
                tuple((a + b) / 2 for a, b in zip(edge.start, edge.end, strict=True))
            )
            label.scale.z = 0.05
            label.color = TEXT
            label.text = edge.type
            markers.append(label)
    return MarkerArray(markers=markers)
