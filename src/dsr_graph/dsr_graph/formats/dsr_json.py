"""Our versioned JSON format for world files and snapshots (schema in docs/FORMAT.md).

    {"format": "dsr-graph", "version": 1, "kind": "world" | "snapshot", "seq": N (snapshots),
     "units": {"length": "m" | "cm" | "mm"} (optional: mm when absent; see units.py),
     "nodes": [{"id", "name", "type", "attrs", "version" (snapshots), "provenance" (optional)}],
     "edges": [{"from": name, "to": name, "type", "attrs", "rt" (RT only), "version" (snapshots),
                "provenance" (optional)}]}

"provenance": {attribute name (or "$rt"): [time, agent]}, who last wrote it (model/provenance.py).

Transactions share the header; see ``transaction.py``.
"""

from __future__ import annotations

from collections.abc import Callable
from operator import attrgetter
from typing import Any

from dsr_graph.exceptions import FormatError, Violation
from dsr_graph.formats import safe_json, units
from dsr_graph.formats.world_builder import WorldBuilder
from dsr_graph.model import provenance, rigid
from dsr_graph.model.graph import Graph
from dsr_graph.model.trusted_loading import SNAPSHOT_COLUMNS
from dsr_graph.model.vocabulary import Vocabulary

FORMAT = "dsr-graph"
VERSION = 1
KINDS = ("world", "snapshot")
COLUMNS = "columns"  # a snapshot's "layout" column by column (to_columns)


def is_dsr_document(doc: Any) -> bool:
    return isinstance(doc, dict) and doc.get("format") == FORMAT


def to_json(graph: Graph, kind: str = "world", seq: int | None = None) -> dict[str, Any]:
    """The whole graph as a document; snapshots also carry versions and the sequence number.
    For speed the document holds the graph's own attribute dicts: encode it (or copy it) before
    the graph changes again, and never restore it with ``trusted=True`` while the graph lives."""
    if kind not in KINDS:
        raise ValueError(f"kind must be one of {KINDS}")
    with_versions = kind == "snapshot"
    ordered = sorted(graph.nodes(), key=attrgetter("id"))
    names = {n.id: n.name for n in ordered}  # edge ends by name, without a lookup per edge
    if with_versions:
        nodes = [
            {"id": n.id, "name": n.name, "type": n.type, "attrs": n.attrs, "version": n.version}
            for n in ordered
        ]
    else:
        nodes = [{"id": n.id, "name": n.name, "type": n.type, "attrs": n.attrs} for n in ordered]
    for item, n in zip(nodes, ordered, strict=True):
        if n.prov:  # who wrote each attribute, and when (model/provenance.py)
            item["provenance"] = n.prov
    edges = []
    for edge in sorted(graph.edges(), key=attrgetter("key")):
        item = {
            "from": names[edge.src],
            "to": names[edge.dst],
            "type": edge.type,
            "attrs": edge.attrs,
        }
        if edge.rt is not None:
            item["rt"] = rigid.to_json(edge.rt)
        if with_versions:
            item["version"] = edge.version
        if edge.prov:
            item["provenance"] = edge.prov
        edges.append(item)
    doc: dict[str, Any] = {"format": FORMAT, "version": VERSION, "kind": kind}
    doc["units"] = {"length": units.METRES}
    if seq is not None:
        doc["seq"] = seq
    doc["nodes"] = nodes
    doc["edges"] = edges
    return doc


def to_columns(doc: dict[str, Any], encode: Callable[[dict[str, Any]], str]) -> dict[str, Any]:
    """A snapshot document (``to_json``'s) column by column, as a replica joining late asks
    for it (``dsr/get_snapshot``'s ``layout``; docs/FORMAT.md, "Columnar snapshots"): the same
    header with ``"layout": "columns"``, and "nodes" and "edges" each an object of lists of one
    length: ``id``, ``name``, ``type`` and ``rest`` for nodes, ``from``, ``to``, ``type`` and
    ``rest`` for edges, ``rest`` the JSON text (``encode``) of the element's other fields."""
    out = {key: value for key, value in doc.items() if key not in SNAPSHOT_COLUMNS}
    out["layout"] = COLUMNS
    for group, keys in SNAPSHOT_COLUMNS.items():
        items = doc.get(group, [])
        identity = keys[:3]
        columns = {key: [item[key] for item in items] for key in identity}
        columns["rest"] = [
            encode({key: value for key, value in item.items() if key not in identity})
            for item in items
        ]
        out[group] = columns
    return out


def rows_of_columns(doc: dict[str, Any], parse=safe_json.loads) -> dict[str, Any]:
    """A columnar snapshot as ``to_json`` writes it (one object per element), or FormatError."""
    out = {key: value for key, value in doc.items() if key not in SNAPSHOT_COLUMNS}
    out.pop("layout")
    for group, keys in SNAPSHOT_COLUMNS.items():
        columns = doc.get(group, {})
        if not isinstance(columns, dict) or not all(
            isinstance(columns.get(key), list) for key in keys
        ):
            raise FormatError(f"snapshot: columnar {group!r} must hold the lists {list(keys)}")
        if len({len(columns[key]) for key in keys}) != 1:
            raise FormatError(f"snapshot: the {group} columns are not of one length")
        rows = []
        for i, values in enumerate(zip(*(columns[key] for key in keys), strict=True)):
            try:
                item = parse(values[3]) if isinstance(values[3], str) else None
            except ValueError as e:
                raise FormatError(f"snapshot: {group}[{i}] rest: {e}") from None
            if not isinstance(item, dict):
                raise FormatError(f"snapshot: {group}[{i}] rest must be a JSON object's text")
            item.update(zip(keys[:3], values[:3], strict=True))
            rows.append(item)
        out[group] = rows
    return out


def _header(doc: Any, source: str) -> str:
    if not isinstance(doc, dict):
        raise FormatError(f"{source}: top level must be a JSON object")
    if doc.get("format") != FORMAT:
        raise FormatError(f'{source}: "format" must be "{FORMAT}", got {doc.get("format")!r}')
    if doc.get("version") != VERSION:
        raise FormatError(
            f"{source}: unsupported version {doc.get('version')!r} (this reader knows {VERSION})"
        )
    kind = doc.get("kind")
    if kind not in KINDS:
        raise FormatError(f'{source}: "kind" must be one of {list(KINDS)}, got {kind!r}')
    layout = doc.get("layout", "")
    if layout not in ("", COLUMNS):
        raise FormatError(f'{source}: "layout" must be "{COLUMNS}" when given, got {layout!r}')
    for key in ("nodes", "edges"):
        if layout and not isinstance(doc.get(key), dict):
            raise FormatError(f'{source}: columnar "{key}" must be an object of lists')
        if not layout and not isinstance(doc.get(key, []), list):
            raise FormatError(f'{source}: "{key}" must be a list')
    return kind


def from_json(
    doc: Any, vocabulary: Vocabulary | None = None, source: str = "world"
) -> tuple[Graph, list[Violation]]:
    """Build a graph from a world or snapshot document; bad elements are reported, not loaded.
    Lengths are converted to metres from the unit the document declares."""
    kind = _header(doc, source)
    doc = units.in_metres(doc, source)
    builder = WorldBuilder(vocabulary, source)
    node_versions: dict[int, int] = {}
    edge_versions = {}
    for i, item in enumerate(doc.get("nodes", [])):
        at = f"{source}: nodes[{i}]"
        if not isinstance(item, dict) or "name" not in item or "type" not in item:
            builder.report("malformed", f"nodes[{i}]", 'a node needs "name" and "type"', at)
            continue
        unknown = set(item) - {"id", "name", "type", "attrs", "version", "provenance"}
        if unknown:
            builder.report(
                "malformed", f"node {item['name']!r}", f"unknown keys {sorted(unknown)}", at
            )
        if builder.node(
            item["name"], item["type"], id=item.get("id"), attrs=item.get("attrs"), at=at
        ):
            node = builder.graph.node(item["name"])
            if kind == "snapshot" and isinstance(item.get("version"), int):
                node_versions[node.id] = item["version"]
            _read_provenance(builder, node, item, f"node {node.name!r}", at)
    for i, item in enumerate(doc.get("edges", [])):
        at = f"{source}: edges[{i}]"
        if not isinstance(item, dict) or not all(k in item for k in ("from", "to", "type")):
            builder.report("malformed", f"edges[{i}]", 'an edge needs "from", "to" and "type"', at)
            continue
        unknown = set(item) - {"from", "to", "type", "attrs", "rt", "version", "provenance"}
        if unknown:
            builder.report(
                "malformed",
                f"edge {item['from']!r}->{item['to']!r} ({item['type']})",
                f"unknown keys {sorted(unknown)}",
                at,
            )
        if builder.edge(
            item["from"],
            item["to"],
            item["type"],
            attrs=item.get("attrs"),
            rt=item.get("rt"),
            at=at,
        ):
            edge = builder.graph.edge(item["from"], item["to"], item["type"])
            if kind == "snapshot" and isinstance(item.get("version"), int):
                edge_versions[edge.key] = item["version"]
            _read_provenance(builder, edge, item, builder.graph.describe_edge(*edge.key), at)
    graph = builder.finish()
    graph.restore_versions(node_versions, edge_versions)
    return graph, builder.violations


def _read_provenance(builder: WorldBuilder, element, item: dict, label: str, at: str) -> None:
    """The element's stamps, when the document has them (optional); bad ones are reported and
    left out, the element kept."""
    if "provenance" not in item:
        return
    names = element.attrs.keys()
    try:
        element.prov = provenance.read(item["provenance"], names, label)
    except FormatError as e:
        builder.report("malformed", label, str(e).removeprefix(f"{label}: "), at)


def _trusted_json(text: str) -> Any:
    return safe_json.loads(text, max_bytes=None, walk=False)


def _element_json(text: str) -> Any:
    return safe_json.loads(text, max_bytes=None)


def snapshot_from_json(
    doc: Any,
    vocabulary: Vocabulary | None = None,
    trusted: bool = False,
    lazy: bool = False,
    attrs_hook=None,
) -> tuple[Graph, int]:
    """A snapshot must load whole: any violation is a ``FormatError`` (it came from a valid graph).
    ``trusted``: it comes straight from a DSR server (a replica's resync), so its elements are not
    checked again, only its structure; then ``lazy`` and ``attrs_hook`` as ``Graph.restore``.
    A columnar one (``to_columns``) is read as it is when trusted and lazy, else as rows."""
    columnar = isinstance(doc, dict) and doc.get("layout") == COLUMNS
    if columnar and _header(doc, "snapshot") != "snapshot":
        raise FormatError('snapshot: "kind" must be "snapshot"')
    if columnar and units.length_unit(doc, "snapshot") != units.METRES:
        raise FormatError('snapshot: a columnar snapshot is in metres ("units")')
    if columnar and not (trusted and lazy):
        doc = rows_of_columns(doc, _trusted_json if trusted else _element_json)
        columnar = False
    if trusted:
        if _header(doc, "snapshot") != "snapshot":
            raise FormatError('snapshot: "kind" must be "snapshot"')
        doc = units.in_metres(doc, "snapshot")
        graph = Graph(vocabulary)
        try:
            if columnar:
                graph.restore_columns(doc["nodes"], doc["edges"], _trusted_json, attrs_hook)
            else:
                graph.restore(doc.get("nodes", []), doc.get("edges", []), lazy, attrs_hook)
        except (KeyError, TypeError, ValueError) as e:
            raise FormatError(f"snapshot is not a valid graph: {e!r}") from e
    else:
        graph, violations = from_json(doc, vocabulary, source="snapshot")
        if violations:
            raise FormatError(
                "snapshot is not a valid graph: " + "; ".join(str(v) for v in violations[:5])
            )
    seq = doc.get("seq", 0)
    if isinstance(seq, bool) or not isinstance(seq, int) or seq < 0:
        raise FormatError(f'snapshot: "seq" must be a non-negative integer, got {seq!r}')
    return graph, seq
