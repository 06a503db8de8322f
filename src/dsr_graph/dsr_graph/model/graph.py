"""The Deep State Representation: a multi-labelled directed graph of symbols and geometry.

Paper, Section II-A. Rules enforced here (each violation names its rule id):

- ``unique-id`` / ``unique-name``: node ids and names are unique; names never change.
- ``unknown-node-type`` / ``unknown-edge-type`` / ``unknown-attribute`` / ``attribute-type``:
  everything is checked against the vocabulary.
- ``no-self-loop``: no edge joins a node to itself (symbolic quiver, property 2).
- ``edge-unique``: one edge per (from, to, type); several types may join the same pair.
- ``rt-rigid``: an RT edge holds a rigid transform; only RT edges do.
- ``rt-single-parent``: a geometric node has at most one RT parent.
- ``rt-acyclic``: RT edges never form a cycle.
- ``rt-orphan``: a node with RT children cannot be deleted (its subtree would lose its poses).
- ``rt-single-tree``: all RT edges form one rooted tree (checked when a transaction ends).

The graph keeps the nodes, the edges and their indexes, and checks every mutation; the RT tree
and its kinematic chains are in ``rt_tree.RtTree``; every mutation records its undo step in
``undo_log.UndoLog`` while ``atomic()`` is active, so that a failing transaction is rolled back
to exactly the state it started from. Nodes and edges are ``elements.py``'s; loading a server's
snapshot without checking it again is ``trusted_loading.py``'s.
"""

from __future__ import annotations

from collections.abc import Iterator, Mapping, Sequence
from contextlib import contextmanager
from typing import Any

import numpy as np

from dsr_graph.exceptions import LookupFailed, RuleViolation, ValueTypeError, Violation
from dsr_graph.model import rigid
from dsr_graph.model.elements import Edge, EdgeKey, Node, NodeRef
from dsr_graph.model.rt_history import RtHistory
from dsr_graph.model.rt_tree import RtTree
from dsr_graph.model.trusted_loading import SNAPSHOT_COLUMNS, TrustedLoading
from dsr_graph.model.undo_log import UndoLog
from dsr_graph.model.values import UINT64_MAX, coerce
from dsr_graph.model.vocabulary import RT, Vocabulary

__all__ = ["SNAPSHOT_COLUMNS", "Edge", "EdgeKey", "Graph", "Node", "NodeRef"]

MAX_NAME_LENGTH = 256


def _fail(rule: str, element: str, message: str) -> None:
    raise RuleViolation(Violation(rule=rule, element=element, message=message))


class Graph(TrustedLoading):
    """The graph model. Pure Python: no ROS import anywhere below this package's node modules."""

    def __init__(self, vocabulary: Vocabulary | None = None):
        self.vocabulary = vocabulary if vocabulary is not None else Vocabulary.default()
        self._nodes: dict[int, Node] = {}
        self._ids: dict[str, int] = {}
        self._edges: dict[EdgeKey, Edge] = {}
        self._out: dict[int, set[EdgeKey]] = {}
        self._in: dict[int, set[EdgeKey]] = {}
        self._by_type: dict[str, set[EdgeKey]] = {}
        self._tree = RtTree()
        self._undo = UndoLog()
        self._next_id = 1
        # a replica's graph: a transform given as a matrix comes from a DSR server, which
        # checked it is rigid, so only its shape is checked again (sensor-rate poses)
        self.trusted_rt = False
        # each RT edge's recent transforms, kept as deltas are applied (rt_history.remember)
        self.rt_history = RtHistory()

    # ------------------------------------------------------------------ naming and lookup
    def node(self, ref: NodeRef) -> Node:
        """The node with this id (int) or name (str); ``LookupFailed`` if there is none."""
        node = self.find(ref)
        if node is None:
            raise LookupFailed(f"no node {ref!r}")
        return node

    def find(self, ref: NodeRef) -> Node | None:
        if isinstance(ref, bool):
            return None
        if isinstance(ref, int):
            return self._nodes.get(ref)
        if isinstance(ref, str):
            node_id = self._ids.get(ref)
            return None if node_id is None else self._nodes[node_id]
        return None

    def __contains__(self, ref: NodeRef) -> bool:
        return self.find(ref) is not None

    def __len__(self) -> int:
        return len(self._nodes)

    def nodes(self) -> Iterator[Node]:
        return iter(self._nodes.values())

    def edges(self) -> Iterator[Edge]:
        return iter(self._edges.values())

    def edge(self, src: NodeRef, dst: NodeRef, type: str) -> Edge | None:
        a, b = self.find(src), self.find(dst)
        if a is None or b is None:
            return None
        return self._edges.get((a.id, b.id, type))

    def out_edges(self, ref: NodeRef) -> list[Edge]:
        return [self._edges[k] for k in self._out.get(self.node(ref).id, ())]

    def in_edges(self, ref: NodeRef) -> list[Edge]:
        return [self._edges[k] for k in self._in.get(self.node(ref).id, ())]

    def edges_of_type(self, type: str) -> list[Edge]:
        return [self._edges[k] for k in self._by_type.get(type, ())]

    def edge_count(self) -> int:
        return len(self._edges)

    def describe_edge(self, src: int, dst: int, type: str) -> str:
        def name(i: int) -> str:
            n = self._nodes.get(i)
            return repr(n.name) if n else f"#{i}"

        return f"edge {name(src)}->{name(dst)} ({type})"

    # ------------------------------------------------------------------ geometry
    def rt_parent(self, ref: NodeRef) -> Node | None:
        parent = self._tree.parent.get(self.node(ref).id)
        return None if parent is None else self._nodes[parent]

    def rt_children(self, ref: NodeRef) -> list[Node]:
        return [self._nodes[c] for c in self._tree.children.get(self.node(ref).id, ())]

    def rt_root(self) -> Node | None:
        """The root of the RT tree (None when there are no RT edges)."""
        if len(self._tree.roots) != 1:
            return None
        return self._nodes[next(iter(self._tree.roots))]

    def is_geometric(self, ref: NodeRef) -> bool:
        """A node is geometric when an RT edge touches it (it is part of the kinematic tree)."""
        return self._tree.is_geometric(self.node(ref).id)

    def transform(self, frm: NodeRef, to: NodeRef) -> np.ndarray:
        """The kinematic chain C(frm, to): a 4x4 matrix mapping coordinates in frame ``to`` into
        frame ``frm`` (``to``'s pose seen from ``frm``, like tf2's lookupTransform(frm, to))."""
        a, b = self._geometric_id(frm), self._geometric_id(to)
        if len(self._tree.roots) > 1:  # only in a loaded world that breaks rt-single-tree
            self._same_tree(a, b)
        return self._tree.transform(a, b)

    def transform_at(self, frm: NodeRef, to: NodeRef, when: float) -> np.ndarray:
        """``transform(frm, to)`` as it was at time ``when`` (seconds since the epoch), from each
        edge's RT history; ``OutsideHistory`` names the edge whose history does not reach it."""
        a, b = self._geometric_id(frm), self._geometric_id(to)
        self._same_tree(a, b)
        up_a, up_b = self._tree.ancestry(a), self._tree.ancestry(b)
        on_b = set(up_b)
        top = next(n for n in up_a if n in on_b)  # the closest common ancestor

        def pose(node: int) -> np.ndarray:  # the node's pose in the common ancestor's frame
            m = np.eye(4)
            while node != top:
                edge = self._tree.edge_to(node)
                label = lambda key=edge.key: self.describe_edge(*key)  # noqa: E731 (on refusal)
                m = self.rt_history.matrix_at(edge.key, edge.rt, when, label) @ m
                node = edge.src
            return m

        return rigid.inverse(pose(a)) @ pose(b)

    def chain(self, frm: NodeRef, to: NodeRef) -> list[str]:
        """Names on the path frm -> closest common ancestor -> to."""
        a, b = self._geometric_id(frm), self._geometric_id(to)
        self._same_tree(a, b)
        return [self._nodes[i].name for i in self._tree.chain(a, b)]

    def _same_tree(self, a: int, b: int) -> None:
        if not self._tree.same_tree(a, b):
            raise LookupFailed(
                f"no kinematic chain joins {self._nodes[a].name!r} and {self._nodes[b].name!r}: "
                "they are in different RT trees"
            )

    def _geometric_id(self, ref: NodeRef) -> int:
        node = self.find(ref)
        if node is None:
            raise LookupFailed(f"no node {ref!r}")
        if not self._tree.is_geometric(node.id):
            raise LookupFailed(
                f"node {node.name!r} is not geometric: no RT edge joins it to the tree"
            )
        return node.id

    # ------------------------------------------------------------------ atomicity
    @contextmanager
    def atomic(self) -> Iterator[None]:
        """All changes inside the block happen, or none: on any exception (including a rule
        broken at the end, such as ``rt-single-tree``) the graph is rolled back exactly."""
        self._undo.begin()
        try:
            yield
            self.check_single_tree()
        except BaseException:
            self._undo.rollback()
            self._tree.clear_cache()
            raise
        finally:
            self._undo.end()

    def check_single_tree(self) -> None:
        if len(self._tree.roots) > 1:
            names = sorted(self._nodes[r].name for r in self._tree.roots)
            _fail(
                "rt-single-tree",
                "graph",
                f"RT edges must form one rooted tree, but there are {len(names)} roots: "
                + ", ".join(repr(n) for n in names),
            )

    # ------------------------------------------------------------------ checks
    def check_attribute(self, element: str, name: Any, value: Any) -> Any:
        """``value`` coerced to the vocabulary's type for ``name``; else ``RuleViolation``."""
        type_name = self.vocabulary.attribute_type(name) if isinstance(name, str) else None
        if type_name is None:
            _fail(
                "unknown-attribute",
                element,
                f"attribute {name!r} is not in the vocabulary (extend it to add one)",
            )
        try:
            return coerce(type_name, value)
        except ValueTypeError as e:
            _fail("attribute-type", element, f"attribute {name!r} must be {type_name}: {e}")

    def _checked_attrs(self, element: str, attrs: Any) -> dict[str, Any]:
        if not isinstance(attrs, Mapping):
            _fail("malformed", element, f"attrs must be an object, got {type(attrs).__name__}")
        return {name: self.check_attribute(element, name, value) for name, value in attrs.items()}

    def _existing(self, ref: NodeRef, element: str) -> Node:
        node = self.find(ref)
        if node is None:
            _fail("node-missing", element, f"node {ref!r} does not exist")
        return node

    def _existing_edge(self, src: NodeRef, dst: NodeRef, type: str) -> Edge:
        a = self._existing(src, f"edge {src!r}->{dst!r} ({type})")
        b = self._existing(dst, f"edge {src!r}->{dst!r} ({type})")
        edge = self._edges.get((a.id, b.id, type))
        if edge is None:
            _fail("edge-missing", self.describe_edge(a.id, b.id, type), "the edge does not exist")
        return edge

    # ------------------------------------------------------------------ node mutations
    def insert_node(
        self, name: str, type: str, id: int | None = None, attrs: Mapping[str, Any] | None = None
    ) -> Node:
        element = f"node {name!r}"
        if (
            not isinstance(name, str)
            or not name
            or name != name.strip()
            or len(name) > MAX_NAME_LENGTH
            or not name.isprintable()
        ):
            _fail(
                "node-name",
                element,
                f"a name is a printable string of 1..{MAX_NAME_LENGTH} characters "
                "with no surrounding blanks",
            )
        if name in self._ids:
            _fail(
                "unique-name",
                element,
                f"a node named {name!r} already exists (id {self._ids[name]})",
            )
        if not isinstance(type, str) or type not in self.vocabulary.node_types:
            _fail(
                "unknown-node-type",
                element,
                f"node type {type!r} is not in the vocabulary (extend it to add one)",
            )
        if id is None:
            id = self._next_id
        elif isinstance(id, bool) or not isinstance(id, int) or not 0 <= id <= UINT64_MAX:
            _fail("node-id", element, f"id must be an integer in [0, 2^64-1], got {id!r}")
        elif id in self._nodes:
            _fail("unique-id", element, f"id {id} is already used by node {self._nodes[id].name!r}")
        node = Node(id, name, type, self._checked_attrs(element, attrs or {}))
        previous_next = self._next_id
        self._nodes[id] = node
        self._ids[name] = id
        self._next_id = max(self._next_id, id + 1)

        def undo() -> None:
            del self._nodes[id]
            del self._ids[name]
            self._next_id = previous_next

        self._undo.record(undo)
        return node

    def delete_node(self, ref: NodeRef) -> None:
        """Delete a node and every edge that touches it. A node with RT children is refused
        (``rt-orphan``): delete or re-parent them first, so no pose is lost silently."""
        node = self._existing(ref, f"node {ref!r}")
        children = self._tree.children.get(node.id)
        if children:
            names = ", ".join(sorted(repr(self._nodes[c].name) for c in children))
            _fail(
                "rt-orphan",
                f"node {node.name!r}",
                f"has RT children ({names}); delete or re-parent them first",
            )
        for key in list(self._out.get(node.id, ())) + list(self._in.get(node.id, ())):
            if key in self._edges:
                self._remove_edge(self._edges[key])
        del self._nodes[node.id]
        del self._ids[node.name]

        def undo() -> None:
            self._nodes[node.id] = node
            self._ids[node.name] = node.id

        self._undo.record(undo)

    def set_node_attrs(self, ref: NodeRef, attrs: Mapping[str, Any]) -> Node:
        node = self._existing(ref, f"node {ref!r}")
        self._set_attrs(node, self._checked_attrs(f"node {node.name!r}", attrs))
        return node

    def remove_node_attrs(self, ref: NodeRef, names: Sequence[str]) -> Node:
        node = self._existing(ref, f"node {ref!r}")
        self._remove_attrs(node, names, f"node {node.name!r}")
        return node

    # ------------------------------------------------------------------ edge mutations
    def insert_edge(
        self,
        src: NodeRef,
        dst: NodeRef,
        type: str,
        attrs: Mapping[str, Any] | None = None,
        rt: Any = None,
    ) -> Edge:
        element = f"edge {src!r}->{dst!r} ({type})"
        a = self._existing(src, element)
        b = self._existing(dst, element)
        element = self.describe_edge(a.id, b.id, type)
        if not isinstance(type, str) or type not in self.vocabulary.edge_types:
            _fail(
                "unknown-edge-type",
                element,
                f"edge type {type!r} is not in the vocabulary (extend it to add one)",
            )
        if a.id == b.id:
            _fail("no-self-loop", element, "an edge may not join a node to itself")
        if (a.id, b.id, type) in self._edges:
            _fail(
                "edge-unique", element, "this edge already exists (one edge per from, to and type)"
            )
        checked_attrs = self._checked_attrs(element, attrs or {})
        matrix = None
        if type == RT:
            matrix = self._checked_rt(element, rt)
            if b.id in self._tree.parent:
                _fail(
                    "rt-single-parent",
                    element,
                    f"{b.name!r} already has the RT parent "
                    f"{self._nodes[self._tree.parent[b.id]].name!r}",
                )
            if b.id in self._tree.ancestry(a.id):
                _fail(
                    "rt-acyclic",
                    element,
                    f"{b.name!r} is an RT ancestor of {a.name!r}: this edge would close a cycle",
                )
        elif rt is not None:
            _fail("rt-rigid", element, "only RT edges carry a transform")
        edge = Edge(a.id, b.id, type, checked_attrs, matrix)
        self._add_edge(edge)
        return edge

    def delete_edge(self, src: NodeRef, dst: NodeRef, type: str) -> None:
        self._remove_edge(self._existing_edge(src, dst, type))

    def set_edge_attrs(
        self, src: NodeRef, dst: NodeRef, type: str, attrs: Mapping[str, Any]
    ) -> Edge:
        edge = self._existing_edge(src, dst, type)
        self._set_attrs(edge, self._checked_attrs(self.describe_edge(*edge.key), attrs))
        return edge

    def remove_edge_attrs(
        self, src: NodeRef, dst: NodeRef, type: str, names: Sequence[str]
    ) -> Edge:
        edge = self._existing_edge(src, dst, type)
        self._remove_attrs(edge, names, self.describe_edge(*edge.key))
        return edge

    def set_rt(self, src: NodeRef, dst: NodeRef, rt: Any) -> Edge:
        """Change the transform of an existing RT edge (a node moved)."""
        edge = self._existing_edge(src, dst, RT)
        matrix = self._checked_rt(edge.key, rt)
        old_matrix, old_version = edge.rt, edge.version
        self.rt_history.before_change(edge.key, old_matrix)
        edge.rt = matrix
        edge.version += 1
        self._tree.invalidate(edge.dst)

        def undo() -> None:
            edge.rt, edge.version = old_matrix, old_version

        self._undo.record(undo)
        return edge

    def _checked_rt(self, element: str | EdgeKey, rt: Any) -> np.ndarray:
        """``rt`` as a rigid 4x4 matrix, else a rule violation naming ``element`` (an edge's
        description, or its key, described only if it is needed)."""
        if self.trusted_rt and isinstance(rt, Mapping) and rt.keys() == {"matrix"}:
            matrix = np.array(rt["matrix"], dtype=float)  # a server's, checked there
            if matrix.shape == (4, 4):
                return matrix
        problem = 'an RT edge needs a transform ("rt")'
        if rt is not None:
            try:
                return rigid.check_rigid(rt) if isinstance(rt, np.ndarray) else rigid.from_json(rt)
            except rigid.NotRigidError as e:
                problem = str(e)
        _fail(
            "rt-rigid",
            element if isinstance(element, str) else self.describe_edge(*element),
            problem,
        )

    # ------------------------------------------------------------------ primitives (with undo)
    def _set_attrs(self, element: Node | Edge, attrs: dict[str, Any]) -> None:
        before = {k: element.attrs[k] for k in attrs if k in element.attrs}
        added = [k for k in attrs if k not in element.attrs]
        old_version = element.version
        element.attrs.update(attrs)
        element.version += 1

        def undo() -> None:
            for k in added:
                del element.attrs[k]
            element.attrs.update(before)
            element.version = old_version

        self._undo.record(undo)

    def _remove_attrs(self, element: Node | Edge, names: Sequence[str], label: str) -> None:
        if isinstance(names, str) or not isinstance(names, (list, tuple)):
            _fail("malformed", label, f"names must be a list of attribute names, got {names!r}")
        for name in names:
            if name not in element.attrs:
                _fail("attribute-missing", label, f"has no attribute {name!r} to remove")
        removed = {name: element.attrs.pop(name) for name in names}
        old_version = element.version
        element.version += 1

        def undo() -> None:
            element.attrs.update(removed)
            element.version = old_version

        self._undo.record(undo)

    def _add_edge(self, edge: Edge) -> None:
        key = edge.key
        self._edges[key] = edge
        self._out.setdefault(edge.src, set()).add(key)
        self._in.setdefault(edge.dst, set()).add(key)
        self._by_type.setdefault(edge.type, set()).add(key)
        if edge.type == RT:
            self._tree.link(edge)
        self._undo.record(lambda: self._unlink_edge(edge))

    def _remove_edge(self, edge: Edge) -> None:
        self._unlink_edge(edge)
        self._undo.record(lambda: self._add_edge(edge))  # a rollback records nothing

    def _unlink_edge(self, edge: Edge) -> None:
        key = edge.key
        del self._edges[key]
        self._out[edge.src].discard(key)
        self._in[edge.dst].discard(key)
        if not self._out[edge.src]:
            del self._out[edge.src]
        if not self._in[edge.dst]:
            del self._in[edge.dst]
        self._by_type[edge.type].discard(key)
        if edge.type == RT:
            self._tree.unlink(edge)
