"""The geometric part of the graph: RT edges as one rooted tree, and kinematic chains.

Indexes: each geometric node's RT parent and children, and the roots. A chain C(a, b) maps
coordinates in frame b into frame a (tf2's lookupTransform(a, b)); it equals
inv(T_w,a) @ T_w,b for the closest common ancestor w (paper, Section II-A), computed from poses
in the root's frame, whose part of the chain cancels out. Each root pose is cached and the
cache is invalidated per subtree when an RT edge changes. Works on node ids; the graph resolves
names and reports errors. Pure (numpy).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from dsr_graph.model import rigid

if TYPE_CHECKING:
    from dsr_graph.model.graph import Edge


class RtTree:
    def __init__(self) -> None:
        self.parent: dict[int, int] = {}
        self.children: dict[int, set[int]] = {}
        self.roots: set[int] = set()
        self._edge_to: dict[int, Edge] = {}  # child id -> its RT edge (which holds the matrix)
        self._pose_cache: dict[int, np.ndarray] = {}  # node id -> pose in the root's frame

    # ------------------------------------------------------------------ structure
    def link(self, edge: Edge) -> None:
        self.parent[edge.dst] = edge.src
        self.children.setdefault(edge.src, set()).add(edge.dst)
        self._edge_to[edge.dst] = edge
        self._update_root(edge.src)
        self._update_root(edge.dst)
        self.invalidate(edge.dst)

    def unlink(self, edge: Edge) -> None:
        self.invalidate(edge.dst)
        del self.parent[edge.dst]
        del self._edge_to[edge.dst]
        self.children[edge.src].discard(edge.dst)
        if not self.children[edge.src]:
            del self.children[edge.src]
        self._update_root(edge.src)
        self._update_root(edge.dst)

    def _update_root(self, node_id: int) -> None:
        if node_id not in self.parent and self.children.get(node_id):
            self.roots.add(node_id)
        else:
            self.roots.discard(node_id)

    def is_geometric(self, node_id: int) -> bool:
        """An RT edge touches the node: it is part of the kinematic tree."""
        return node_id in self.parent or bool(self.children.get(node_id))

    def edge_to(self, child: int) -> Edge:
        """The RT edge from the node's parent to it."""
        return self._edge_to[child]

    def ancestry(self, node_id: int) -> list[int]:
        """The node, its parent, ... up to its root."""
        path = [node_id]
        while path[-1] in self.parent:
            path.append(self.parent[path[-1]])
        return path

    def same_tree(self, a: int, b: int) -> bool:
        return self.ancestry(a)[-1] == self.ancestry(b)[-1]

    # ------------------------------------------------------------------ kinematic chains
    def transform(self, a: int, b: int) -> np.ndarray:
        """C(a, b): b's pose seen from a (both geometric, in one tree)."""
        if a == b:
            return np.eye(4)
        return rigid.inverse(self._pose(a)) @ self._pose(b)

    def chain(self, a: int, b: int) -> list[int]:
        """The path a -> closest common ancestor -> b."""
        up_a = self.ancestry(a)
        on_a = set(up_a)
        down: list[int] = []
        node = b
        while node not in on_a:
            down.append(node)
            node = self.parent[node]
        return up_a[: up_a.index(node) + 1] + list(reversed(down))

    def _pose(self, node_id: int) -> np.ndarray:
        cached = self._pose_cache.get(node_id)
        if cached is not None:
            return cached
        # Walk up to the first cached ancestor (or the root), then come down caching each pose.
        chain = []
        node = node_id
        while node not in self._pose_cache and node in self.parent:
            chain.append(node)
            node = self.parent[node]
        pose = self._pose_cache.get(node)
        if pose is None:  # node is the root
            pose = np.eye(4)
            self._pose_cache[node] = pose
        for child in reversed(chain):
            pose = pose @ self._edge_to[child].rt
            self._pose_cache[child] = pose
        return pose

    def invalidate(self, node_id: int) -> None:
        """The pose of this node changed: forget its cached pose and its subtree's."""
        # An ancestor is always cached before its descendants, so an uncached node has no
        # cached descendants and the walk can stop there.
        stack = [node_id]
        while stack:
            n = stack.pop()
            if self._pose_cache.pop(n, None) is not None:
                stack.extend(self.children.get(n, ()))

    def clear_cache(self) -> None:
        self._pose_cache.clear()
