"""``DSRGraph``: CORTEX's graph API (python_api.cpp) on the DSR suite's graph.

Reads come from the agent's replica; every write is a transaction through the server (policy,
claims and identity apply as to any agent), and returns what pydsr returns: the new id, True, or
None / False when the server refuses it (the reason is logged on the "pydsr" logger).
"""

from __future__ import annotations

import logging
import queue
import re
import threading
from collections.abc import Callable
from pathlib import Path
from typing import Any

from dsr_graph.exceptions import TimedOutError
from dsr_graph.formats import cortex
from dsr_graph.formats.world_files import read_world, write_json_atomically
from dsr_graph.model.graph import Graph
from dsr_graph.model.vocabulary import RT
from pydsr import convert
from pydsr.elements import Edge, Node, set_local_agent_id
from pydsr.links import LocalLink, RosLink
from pydsr.signals import Event, Mirror, signal_type

log = logging.getLogger("pydsr")
WRITE_TIMEOUT = 30.0  # seconds a write waits for the server's verdict
JOIN_TIMEOUT = 30.0  # seconds to find the server and load its snapshot


def ros_node_name(name: str) -> str:
    """CORTEX's agent name as a ROS node name (letters, digits, underscores; not a digit first)."""
    cleaned = re.sub(r"[^A-Za-z0-9_]", "_", name) or "pydsr"
    return cleaned if not cleaned[0].isdigit() else f"a{cleaned}"


class DSRGraph:
    """``DSRGraph(root, name, id, dsr_input_file="", all_same_host=True)``.

    With a world file (``dsr_input_file``, or ``config_file``) the graph is this process's own,
    fresh each time, loaded from it (CORTEX's format or the DSR's). Without, it joins the running
    ``dsr_server`` as the agent ``/<name>``. ``root`` and ``all_same_host`` are CORTEX's and
    change nothing here (the transport is ROS 2)."""

    def __init__(
        self,
        root: int = 0,
        name: str = "pydsr",
        id: int = 0,
        dsr_input_file: str = "",
        all_same_host: bool = True,
        config_file: str | None = None,
    ):
        self._agent_id = int(id)
        self._agent_name = name
        set_local_agent_id(self._agent_id)
        node_name = ros_node_name(name)
        path = dsr_input_file or config_file or ""
        if path:
            world = read_world(Path(path))
            for violation in world.violations:
                log.warning("%s: left out: %s", path, violation)
            self._link: LocalLink | RosLink = LocalLink(world.graph, f"/{node_name}")
        else:
            self._link = RosLink(node_name, JOIN_TIMEOUT)
        self._handlers: dict[signal_type, list[Callable[..., Any]]] = {}
        self._events: queue.SimpleQueue[Event | None] = queue.SimpleQueue()
        self._dispatching = False
        with self._link.lock:
            self._mirror = Mirror(self._link.graph)
            self._link.add_listener(self._on_deltas)
        self._dispatcher = None
        if isinstance(self._link, RosLink):  # handlers run apart from the ROS thread: they
            # may write, and a write waits for a verdict that thread brings
            self._dispatcher = threading.Thread(target=self._dispatch_forever, daemon=True)
            self._dispatcher.start()

    # -- CORTEX's identity ---------------------------------------------------------------------
    def get_agent_id(self) -> int:
        return self._agent_id

    def get_agent_name(self) -> str:
        return self._agent_name

    # -- reads ----------------------------------------------------------------------------------
    @property
    def _graph(self) -> Graph:
        return self._link.graph

    def get_node(self, ref: int | str) -> Node | None:
        with self._link.lock:
            node = self._graph.find(ref) if isinstance(ref, (int, str)) else None
            return None if node is None else convert.node_of(self._graph, node)

    def get_node_root(self) -> Node | None:
        with self._link.lock:
            root = self._graph.rt_root() or self._graph.find("root")
            return None if root is None else convert.node_of(self._graph, root)

    def get_nodes(self) -> list[Node]:
        with self._link.lock:
            return [convert.node_of(self._graph, n) for n in self._graph.nodes()]

    def get_nodes_by_type(self, type: str) -> list[Node]:
        with self._link.lock:
            g = self._graph
            return [convert.node_of(g, n) for n in g.nodes() if n.type == type]

    def get_name_from_id(self, id: int) -> str | None:
        with self._link.lock:
            node = self._graph.find(int(id))
            return None if node is None else node.name

    def get_id_from_name(self, name: str) -> int | None:
        with self._link.lock:
            node = self._graph.find(str(name))
            return None if node is None else node.id

    def get_edge(self, frm: int | str, to: int | str, type: str) -> Edge | None:
        with self._link.lock:
            g = self._graph
            if frm not in g or to not in g:
                return None
            edge = g.edge(frm, to, type)
            return None if edge is None else convert.edge_of(g, edge)

    def get_edges(self) -> list[Edge]:
        with self._link.lock:
            return [convert.edge_of(self._graph, e) for e in self._graph.edges()]

    def get_edges_by_type(self, type: str) -> list[Edge]:
        with self._link.lock:
            g = self._graph
            return [convert.edge_of(g, e) for e in g.edges_of_type(type)]

    def get_edges_to_id(self, id: int) -> list[Edge]:
        with self._link.lock:
            g = self._graph
            if int(id) not in g:
                return []
            return [convert.edge_of(g, e) for e in g.in_edges(int(id))]

    def write_to_json_file(self, file: str, skip_atts: list[str] | None = None) -> None:
        """The graph in CORTEX's format, without the attributes named in ``skip_atts``."""
        skip = set(skip_atts or ())
        with self._link.lock:
            doc = cortex.to_cortex(self._graph)
        for symbol in doc["DSRModel"]["symbols"].values():
            for name in skip & set(symbol["attribute"]):
                del symbol["attribute"][name]
            for link in symbol["links"]:
                for name in skip & set(link["linkAttribute"]):
                    del link["linkAttribute"][name]
        write_json_atomically(doc, file)

    # -- writes ---------------------------------------------------------------------------------
    def insert_node(self, node: Node) -> int | None:
        """The new node's id; None if a node of that name exists or the server refuses it. A
        node without a name is named ``<type>_<id>``, as CORTEX does."""
        with self._link.lock:
            g = self._graph
            if node.name and node.name in g:
                log.warning("insert_node: a node named %r already exists", node.name)
                return None
            new_id = max((n.id for n in g.nodes()), default=0) + 1
            name = node.name or f"{node.type}_{new_id}"
            attrs = {k: convert.graph_value(g, k, a) for k, a in node.attrs.items()}
            ops: list[dict[str, Any]] = [
                {"op": "insert_node", "name": name, "type": node.type, "attrs": attrs}
            ]
            if not node.name:
                ops[0]["id"] = new_id
            for edge in node.edges.values():
                ops += self._insert_edge_ops(g, edge, origin=name)
        result = self._write(ops, f"insert_node {name!r}")
        if result is None:
            return None
        return next(op["id"] for op in result["ops"] if op["op"] == "insert_node")

    def update_node(self, node: Node) -> bool:
        """Its attributes become the node's (added, changed and removed ones)."""
        with self._link.lock:
            g = self._graph
            current = g.find(node.id)
            if current is None or current.name != node.name:
                log.warning("update_node: no node %r with id %s", node.name, node.id)
                return False
            sets, removes = convert.attr_changes(g, current.attrs, node.attrs)
        ops = []
        if sets:
            ops.append({"op": "set_node_attrs", "node": node.id, "attrs": sets})
        if removes:
            ops.append({"op": "remove_node_attrs", "node": node.id, "names": removes})
        return not ops or self._write(ops, f"update_node {node.name!r}") is not None

    def delete_node(self, ref: int | str) -> bool:
        with self._link.lock:
            if ref not in self._graph:
                return False
        return self._write([{"op": "delete_node", "node": ref}], f"delete_node {ref!r}") is not None

    def insert_or_assign_edge(self, edge: Edge) -> bool:
        with self._link.lock:
            g = self._graph
            ops = self._edge_ops(g, edge)
        if ops is None:
            return False
        label = f"insert_or_assign_edge {edge.origin}->{edge.destination} ({edge.type})"
        return not ops or self._write(ops, label) is not None

    def delete_edge(self, frm: int | str, to: int | str, type: str) -> bool:
        with self._link.lock:
            g = self._graph
            if frm not in g or to not in g or g.edge(frm, to, type) is None:
                return False
        op = {"op": "delete_edge", "from": frm, "to": to, "type": type}
        return self._write([op], f"delete_edge {frm}->{to} ({type})") is not None

    def _edge_ops(self, g: Graph, edge: Edge) -> list[dict[str, Any]] | None:
        for end in (edge.origin, edge.destination):
            if end not in g:
                log.warning("insert_or_assign_edge: no node with id %s", end)
                return None
        current = g.edge(edge.origin, edge.destination, edge.type)
        if current is None:
            return self._insert_edge_ops(g, edge, origin=edge.origin)
        key = {"from": edge.origin, "to": edge.destination, "type": edge.type}
        sets, removes = convert.attr_changes(g, current.attrs, edge.attrs, rt=edge.type == RT)
        ops: list[dict[str, Any]] = []
        if sets:
            ops.append({"op": "set_edge_attrs", **key, "attrs": sets})
        if removes:
            ops.append({"op": "remove_edge_attrs", **key, "names": removes})
        rt = convert.wanted_rt(edge, current)
        if rt is not None:
            ops.append({"op": "set_rt", "from": edge.origin, "to": edge.destination, "rt": rt})
        return ops

    def _insert_edge_ops(self, g: Graph, edge: Edge, origin: int | str) -> list[dict[str, Any]]:
        attrs = {
            k: convert.graph_value(g, k, a)
            for k, a in edge.attrs.items()
            if not (edge.type == RT and k in convert.RT_ATTRS)
        }
        op: dict[str, Any] = {
            "op": "insert_edge",
            "from": origin,
            "to": edge.destination,
            "type": edge.type,
            "attrs": attrs,
        }
        ops: list[dict[str, Any]] = []
        if edge.type == RT:
            op["rt"] = convert.wanted_rt(edge) or convert.rt_of([0, 0, 0], [0, 0, 0])
            parent = g.rt_parent(edge.destination) if edge.destination in g else None
            if parent is not None:  # CORTEX moves a node to its new parent
                ops.append(
                    {"op": "delete_edge", "from": parent.id, "to": edge.destination, "type": RT}
                )
        return ops + [op]

    def _write(self, ops: list[dict[str, Any]], what: str) -> dict[str, Any] | None:
        """The delta of an accepted write; None (logged) when it was refused."""
        try:
            result = self._link.transact({"ops": ops}, WRITE_TIMEOUT)
        except TimedOutError as e:
            log.error("%s: %s", what, e)
            return None
        finally:
            self._dispatch()
        if not result.accepted:
            log.warning("%s refused: %s", what, result.error or result.reason)
            return None
        return result.delta

    # -- signals --------------------------------------------------------------------------------
    def _connect(self, kind: signal_type, fn: Callable[..., Any]) -> None:
        self._handlers.setdefault(kind, []).append(fn)

    def _on_deltas(self, deltas: list[dict[str, Any]], resynced: bool) -> None:
        """(The link's thread, under its lock.) Every change as CORTEX's signals, queued."""
        events = self._mirror.resync(self._graph) if resynced else []
        for delta in deltas:
            if not resynced:
                events += self._mirror.advance(delta)
        for event in events:
            self._events.put(event)

    def _dispatch(self) -> None:
        """(The caller's thread, local graphs.) Run the queued signals, not re-entered."""
        if self._dispatcher is not None or self._dispatching:
            return
        self._dispatching = True
        try:
            while True:
                try:
                    event = self._events.get_nowait()
                except queue.Empty:
                    return
                self._call(event)
        finally:
            self._dispatching = False

    def _dispatch_forever(self) -> None:
        while (event := self._events.get()) is not None:
            self._call(event)

    def _call(self, event: Event) -> None:
        kind, args = event
        for fn in list(self._handlers.get(kind, ())):
            try:
                fn(*args)
            except Exception:  # a handler's bug must not stop the others, nor the graph
                log.exception("a %s handler failed", kind.name)

    def close(self) -> None:
        """Leave the DSR (the agent's node goes away); also done at exit."""
        if self._dispatcher is not None:
            self._events.put(None)
        self._link.close()

    def __del__(self) -> None:
        try:
            self.close()
        except Exception:
            pass
