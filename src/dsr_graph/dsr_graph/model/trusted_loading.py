"""Loading a snapshot a DSR server wrote into a new graph without checking each element again
(the server only ever holds a valid graph): all at once, or lazily for a replica (each node
built when first used, the edges with their indexes and the RT tree when any edge is). A part of
``graph.Graph``, kept apart because it trusts what it loads while the rest checks everything."""

from __future__ import annotations

import weakref
from collections import deque
from collections.abc import Callable, Iterator, Mapping, Sequence
from functools import partial
from operator import itemgetter
from typing import Any

import numpy as np

from dsr_graph.model.elements import Edge, EdgeKey, Node, interned_provenance, node_of
from dsr_graph.model.lazy_nodes import LazyNodes
from dsr_graph.model.rt_tree import RtTree
from dsr_graph.model.values import BINARY, coerce
from dsr_graph.model.vocabulary import RT

SNAPSHOT_COLUMNS = {
    "nodes": ("id", "name", "type", "rest"),
    "edges": ("from", "to", "type", "rest"),
}

# what a lazily restored graph builds when an edge is first used
EDGE_INDEXES = ("_edges", "_out", "_in", "_by_type", "_tree")


class PendingIndex:
    """Stands for one of a lazily restored graph's edge indexes (``EDGE_INDEXES``) until any of
    them is first used: then the graph's edges, their indexes and the RT tree are built and put
    in their places, so that every later use is of a plain dict (or ``RtTree``). Holds its graph
    weakly: a graph replaced before its edges were used is freed by reference counting. (Not a
    ``__getattr__`` on ``Graph``: CPython does not specialise attribute access on a class that
    has one, which made every change to a server's graph 15% slower; nor a subclass the graph
    turns into and back, which had done it before.)"""

    __slots__ = ("_graph", "_name")

    def __init__(self, graph: TrustedLoading, name: str):
        self._graph = weakref.ref(graph)
        self._name = name

    def _built(self) -> Any:
        graph = self._graph()
        graph._build_pending_edges()
        return getattr(graph, self._name)

    def __getattr__(self, attr: str) -> Any:  # a method of the index: get, values, link ...
        return getattr(self._built(), attr)

    def __getitem__(self, key: Any) -> Any:
        return self._built()[key]

    def __setitem__(self, key: Any, value: Any) -> None:
        self._built()[key] = value

    def __delitem__(self, key: Any) -> None:
        del self._built()[key]

    def __contains__(self, key: Any) -> bool:
        return key in self._built()

    def __iter__(self) -> Iterator[Any]:
        return iter(self._built())

    def __len__(self) -> int:
        return len(self._built())


class TrustedLoading:
    """``Graph``'s trusted loading (its indexes are the graph's own)."""

    def restore(
        self,
        nodes: Sequence[Mapping[str, Any]],
        edges: Sequence[Mapping[str, Any]],
        lazy: bool = False,
        attrs_hook: Callable[[dict[str, Any]], dict[str, Any]] | None = None,
    ) -> None:
        """Load a snapshot written by a DSR server, which only ever holds a valid graph, into this
        new graph without checking each element again (a late joiner of a 100k-node graph would
        spend seconds on it). The attribute dicts of the freshly parsed document are taken over,
        not copied. ``attrs_hook`` (a replica's: binary values by reference) rewrites each
        element's attributes; then the binary values, base64 in the document, are decoded.

        ``lazy`` (a replica): only the nodes' ids and names are indexed now and each node is
        built when first used (``LazyNodes``); the edges, their indexes and the RT tree when any
        edge is first used (``PendingIndex``). The document's structure is checked now all the
        same (ids, names, types, edge ends): a malformed one is refused here, not later."""
        if self._nodes or self._ids:
            raise ValueError("restore loads a new, empty graph")
        decode = self._attrs_decoder(attrs_hook)
        if not lazy:
            for n in nodes:
                node = node_of(decode, n)
                self._nodes[node.id] = node
                self._ids[node.name] = node.id
            self._next_id = max(self._nodes, default=0) + 1
            self._add_edges(edges, decode)
            return
        ids = list(map(itemgetter("id"), nodes))
        names = list(map(itemgetter("name"), nodes))
        deque(map(itemgetter("type"), nodes), maxlen=0)  # KeyError now for a node without one
        deque(map(itemgetter("type"), edges), maxlen=0)  # the same for an edge
        self._restore_lazily(
            ids,
            names,
            dict(zip(ids, nodes, strict=True)),
            partial(node_of, decode),
            map(itemgetter("from"), edges),
            map(itemgetter("to"), edges),
            (edges, decode),
        )

    def restore_columns(
        self,
        nodes: Mapping[str, Sequence[Any]],
        edges: Mapping[str, Sequence[Any]],
        parse: Callable[[str], dict[str, Any]],
        attrs_hook: Callable[[dict[str, Any]], dict[str, Any]] | None = None,
    ) -> None:
        """``restore(lazy=True)`` of a columnar snapshot (``dsr_json.to_columns``): the nodes'
        ``id``, ``name``, ``type`` and ``rest`` as four lists, the edges' ``from``, ``to``,
        ``type`` and ``rest``; ``rest`` is the JSON text of an element's other fields, given to
        ``parse`` only when that element is built. A late joiner so never makes the objects of
        the elements it does not use (parsing a 100k-node snapshot took 0.19 s as rows, 0.06 s
        as columns)."""
        if self._nodes or self._ids:
            raise ValueError("restore loads a new, empty graph")
        decode = self._attrs_decoder(attrs_hook)
        ids, names, types, rests = (nodes[k] for k in SNAPSHOT_COLUMNS["nodes"])
        froms, tos, edge_types, edge_rests = (edges[k] for k in SNAPSHOT_COLUMNS["edges"])
        for group, columns in (
            ("nodes", (ids, names, types, rests)),
            ("edges", (froms, tos, edge_types, edge_rests)),
        ):
            if not all(isinstance(c, list) for c in columns) or len(set(map(len, columns))) != 1:
                raise ValueError(f"the {group} columns must be lists of one length")
        if not set(map(type, types)) | set(map(type, edge_types)) <= {str}:
            raise TypeError("element types must be strings")
        if not set(map(type, rests)) | set(map(type, edge_rests)) <= {str}:
            raise TypeError("each element's rest must be a JSON text (a string)")

        def built(row: tuple[int, str, str, str]) -> Node:
            item = parse(row[3])
            item["id"], item["name"], item["type"] = row[:3]
            return node_of(decode, item)

        def edge_items() -> Iterator[dict[str, Any]]:
            for src, dst, kind, rest in zip(froms, tos, edge_types, edge_rests, strict=True):
                item = parse(rest)
                item["from"], item["to"], item["type"] = src, dst, kind
                yield item

        self._restore_lazily(
            ids,
            names,
            dict(zip(ids, zip(ids, names, types, rests, strict=True), strict=True)),
            built,
            froms,
            tos,
            (edge_items(), decode),
        )

    def _restore_lazily(self, ids, names, raw_nodes, build, froms, tos, pending_edges) -> None:
        """The lazy restore: ids and names indexed and the structure checked now, each node built
        from ``raw_nodes[id]`` by ``build`` when first used, the edges from ``pending_edges``
        when one is first used."""
        self._ids.update(zip(names, ids, strict=True))
        if len(self._ids) != len(ids) or len(set(ids)) != len(ids):
            raise ValueError("node ids or names repeat")
        if not set(map(type, ids)) <= {int} or not set(map(type, names)) <= {str}:
            raise TypeError("node ids must be integers and names strings")
        unknown = set(froms).difference(self._ids) | set(tos).difference(self._ids)
        if unknown:
            raise KeyError(f"edges join nodes not in the snapshot: {sorted(map(str, unknown))[:3]}")
        self._nodes = LazyNodes(raw_nodes, build)
        self._next_id = max(ids, default=0) + 1
        self._pending_edges = pending_edges
        for name in EDGE_INDEXES:  # built on first use
            setattr(self, name, PendingIndex(self, name))

    def _build_pending_edges(self) -> None:
        """The edges of a lazy restore, their indexes and the RT tree, at the first use of one."""
        edges, decode = self._pending_edges
        del self._pending_edges
        self._edges, self._out, self._in, self._by_type = {}, {}, {}, {}
        self._tree = RtTree()
        self._add_edges(edges, decode)

    def _add_edges(self, edges: Sequence[Mapping[str, Any]], decode) -> None:
        """A trusted snapshot's edges and their indexes (one pass, everything inlined)."""
        ids = self._ids
        edges_by_key, out, into, by_type = self._edges, self._out, self._in, self._by_type
        for e in edges:
            rt = e.get("rt")
            stamps = e.get("provenance")
            edge = Edge(
                ids[e["from"]],
                ids[e["to"]],
                e["type"],
                decode(e.get("attrs") or {}),
                None if rt is None else np.array(rt["matrix"], dtype=float),
                e.get("version", 1),
                interned_provenance(stamps) if stamps else None,
            )
            key = (edge.src, edge.dst, edge.type)
            edges_by_key[key] = edge
            if edge.src in out:
                out[edge.src].add(key)
            else:
                out[edge.src] = {key}
            if edge.dst in into:
                into[edge.dst].add(key)
            else:
                into[edge.dst] = {key}
            if edge.type in by_type:
                by_type[edge.type].add(key)
            else:
                by_type[edge.type] = {key}
            if edge.type == RT:
                self._tree.link(edge)

    def _attrs_decoder(self, hook: Callable[[dict[str, Any]], dict[str, Any]] | None):
        """attrs -> attrs rewritten by ``hook``, then with their binary values decoded."""
        decode = self._binary_decoder(
            {name for name, kind in self.vocabulary.attributes.items() if kind in BINARY}
        )
        if hook is None:
            return decode
        return lambda attrs: decode(hook(attrs))

    def _binary_decoder(self, names: set[str]):
        """attrs -> attrs with the binary values among ``names`` decoded (the same dict)."""
        if not names:
            return lambda attrs: attrs
        kinds = self.vocabulary.attributes  # not self: a lazy graph keeps this, and no cycle

        def decode(attrs: dict[str, Any]) -> dict[str, Any]:
            if not names.isdisjoint(attrs):
                for name in names.intersection(attrs):
                    attrs[name] = coerce(kinds[name], attrs[name])
            return attrs

        return decode

    # ------------------------------------------------------------------ versions (snapshots)
    def restore_versions(
        self, node_versions: Mapping[int, int], edge_versions: Mapping[EdgeKey, int]
    ) -> None:
        """Set versions as read from a snapshot (loading is not a change)."""
        for node_id, version in node_versions.items():
            self._nodes[node_id].version = version
        for key, version in edge_versions.items():
            self._edges[key].version = version
