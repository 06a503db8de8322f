"""CORTEX's ``rt_api`` and ``inner_api`` (python_api.cpp): RT edges and the kinematic tree, in
CORTEX's millimetres. ``inner_api``'s first frame argument is the one the answer is expressed in
(CORTEX binds it under the name ``orig``, its C++ calls it ``dest``: the order is what counts).

``timestamp``: 0 (CORTEX's default) is the graph as it is now; any other is a time in ns since
the epoch (CORTEX's), answered from the RT history the replica keeps (interpolated between the
two nearest values); a time the history does not hold gets None, the reason logged.
"""

from __future__ import annotations

import logging
from collections.abc import Sequence
from typing import Any

import numpy as np
from transforms3d import euler

from dsr_graph.exceptions import LookupFailed
from dsr_graph.model import rigid
from dsr_graph.model.vocabulary import RT
from pydsr import convert
from pydsr.elements import Attribute, Edge, Node

log = logging.getLogger("pydsr")


def _seconds(timestamp: int) -> float:
    return float(timestamp) / 1e9


class rt_api:  # noqa: N801 (CORTEX's name)
    def __init__(self, graph: Any):
        self._g = graph

    def insert_or_assign_edge_RT(  # noqa: N802
        self, node: Node, to: int, trans: Sequence[float], rot_euler: Sequence[float]
    ) -> bool:
        """The RT edge ``node`` -> ``to`` with this pose (mm, radians); ``to`` leaves its old
        parent, as in CORTEX."""
        edge = Edge(int(to), node.id, RT, self._g.get_agent_id())
        edge.attrs[convert.RT_TRANSLATION] = Attribute(np.asarray(trans, dtype=np.float32))
        edge.attrs[convert.RT_ROTATION] = Attribute(np.asarray(rot_euler, dtype=np.float32))
        if self._g.get_node(node.id) is None:
            log.warning("insert_or_assign_edge_RT: no node with id %s", node.id)
            return False
        current = self._g.get_edge(node.id, int(to), RT)
        if current is not None:  # keep its other attributes
            for name, attribute in current.attrs.items():
                edge.attrs.setdefault(name, attribute)
        return self._g.insert_or_assign_edge(edge)

    @staticmethod
    def get_edge_RT(node: Node, to: int) -> Edge | None:  # noqa: N802
        return node.edges.get((int(to), RT))

    def get_RT_pose_from_parent(self, node: Node) -> np.ndarray | None:  # noqa: N802
        """The node's pose in its RT parent's frame (4x4, mm)."""
        with self._g._link.lock:
            g = self._g._graph
            if node.id not in g:
                return None
            parent = g.rt_parent(node.id)
            if parent is None:
                return None
            return convert.matrix_mm(g.edge(parent.id, node.id, RT).rt)

    def get_edge_RT_as_rtmat(self, edge: Edge, timestamp: int = 0) -> np.ndarray | None:  # noqa: N802
        """The edge's pose (4x4, mm): as the edge says (timestamp 0), or at that time."""
        if timestamp:
            return self._past(edge.origin, edge.destination, timestamp)
        rt = convert.wanted_rt(edge)
        if rt is None:
            return None
        return convert.matrix_mm(
            rigid.from_translation_euler(rt["translation"], rt["rotation_euler_xyz"])
        )

    def _past(self, frm: int, to: int, timestamp: int) -> np.ndarray | None:
        with self._g._link.lock:
            g = self._g._graph
            edge = g.edge(frm, to, RT)
            if edge is None:
                return None
            label = lambda: g.describe_edge(*edge.key)  # noqa: E731 (named on refusal)
            try:
                matrix = g.rt_history.matrix_at(edge.key, edge.rt, _seconds(timestamp), label)
            except LookupFailed as e:
                log.warning("%s", e)
                return None
        return convert.matrix_mm(matrix)

    def get_translation(self, node_id: int, to: int, timestamp: int = 0) -> np.ndarray | None:
        """The translation (mm) of the RT edge ``node_id`` -> ``to`` (now, or at that time)."""
        if timestamp:
            past = self._past(int(node_id), int(to), timestamp)
            return None if past is None else past[:3, 3]
        with self._g._link.lock:
            g = self._g._graph
            if node_id not in g or to not in g:
                return None
            edge = g.edge(int(node_id), int(to), RT)
            return None if edge is None else edge.rt[:3, 3] * convert.MM


class inner_api:  # noqa: N801 (CORTEX's name)
    def __init__(self, graph: Any):
        self._g = graph

    def get_transformation_matrix(
        self, orig: str, dest: str, timestamp: int = 0
    ) -> np.ndarray | None:
        """The 4x4 (mm) taking coordinates in frame ``dest`` to frame ``orig`` (CORTEX's names),
        now or at that time."""
        with self._g._link.lock:
            g = self._g._graph
            try:
                if timestamp:
                    return convert.matrix_mm(g.transform_at(orig, dest, _seconds(timestamp)))
                return convert.matrix_mm(g.transform(orig, dest))
            except LookupFailed as e:
                log.warning("get_transformation_matrix(%r, %r): %s", orig, dest, e)
                return None

    def get_rotation_matrix(self, orig: str, dest: str, timestamp: int = 0) -> np.ndarray | None:
        m = self.get_transformation_matrix(orig, dest, timestamp)
        return None if m is None else m[:3, :3]

    def get_translation_vector(self, orig: str, dest: str, timestamp: int = 0) -> np.ndarray | None:
        m = self.get_transformation_matrix(orig, dest, timestamp)
        return None if m is None else m[:3, 3]

    def get_euler_xyz_angles(self, orig: str, dest: str, timestamp: int = 0) -> np.ndarray | None:
        m = self.get_transformation_matrix(orig, dest, timestamp)
        return None if m is None else np.array(euler.mat2euler(m[:3, :3], axes=rigid.EULER_AXES))

    def transform(self, orig: str, *args: Any, **kwargs: Any) -> np.ndarray | None:
        """``transform(orig, dest, timestamp=0)``: ``dest``'s origin in frame ``orig`` (mm);
        ``transform(orig, vector, dest, timestamp=0)``: the point ``vector`` (mm, in ``dest``)."""
        vector, dest, timestamp = _point_args(args, kwargs, 3)
        m = self.get_transformation_matrix(orig, dest, timestamp)
        if m is None:
            return None
        return m[:3, :3] @ vector + m[:3, 3]

    def transform_axis(self, orig: str, *args: Any, **kwargs: Any) -> np.ndarray | None:
        """As ``transform``, with an oriented point ``[x, y, z, rx, ry, rz]`` (mm, radians)."""
        vector, dest, timestamp = _point_args(args, kwargs, 6)
        m = self.get_transformation_matrix(orig, dest, timestamp)
        if m is None:
            return None
        point = m[:3, :3] @ vector[:3] + m[:3, 3]
        axes = m[:3, :3] @ euler.euler2mat(*vector[3:], axes=rigid.EULER_AXES)
        return np.concatenate([point, euler.mat2euler(axes, axes=rigid.EULER_AXES)])


def _point_args(args: tuple, kwargs: dict, size: int) -> tuple[np.ndarray, str, int]:
    """(vector, dest, timestamp) of CORTEX's two overloads: (dest[, t]) or (vector, dest[, t])."""
    args = list(args)
    if args and not isinstance(args[0], str):
        vector = args.pop(0)
    else:
        vector = kwargs.pop("vector", np.zeros(size))
    dest = args.pop(0) if args else kwargs.pop("dest")
    timestamp = args.pop(0) if args else kwargs.pop("timestamp", 0)
    if args or kwargs:
        raise TypeError(f"unexpected arguments {args or ''} {kwargs or ''}".strip())
    vector = np.asarray(vector, dtype=float).ravel()
    if vector.shape != (size,):
        raise TypeError(f"the vector must have {size} numbers, got {vector.shape[0]}")
    return vector, dest, int(timestamp)
