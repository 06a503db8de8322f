"""RoboComp CORTEX world files (the C++ DSR's JSON), read and written.

    {"DSRModel": {"symbols": {"<id>": {"id", "type", "name",
        "attribute": {name: {"type": code, "value": v}},
        "links": [{"src", "dst", "label", "linkAttribute": {name: {"type": code, "value": v}}}]}}}}

Type codes: 0 string, 1 int32, 2 float, 3 vector<float>, 4 bool, 5 vector<uint8>, 6 uint32,
7 uint64 (written as a string). ``src``/``dst`` are ids, as strings in some files and integers in
others. An ``RT`` link's ``rt_translation`` and ``rt_rotation_euler_xyz`` (radians) give
Translation * Rx * Ry * Rz: the child's pose in the parent's frame. CORTEX's lengths are
millimetres: translations are converted to the DSR's metres when read, and back when written.
"""

from __future__ import annotations

from typing import Any

from dsr_graph.exceptions import FormatError, Violation
from dsr_graph.formats import units
from dsr_graph.formats.world_builder import WorldBuilder
from dsr_graph.model import rigid
from dsr_graph.model.binary import is_binary
from dsr_graph.model.graph import Graph
from dsr_graph.model.vocabulary import RT, Vocabulary

TYPE_CODES = {
    "string": 0,
    "int": 1,
    "float": 2,
    "float_vector": 3,
    "bool": 4,
    "byte_vector": 5,
    "uint": 6,
    "uint64": 7,
    # binary values are CORTEX's byte vectors of the same bytes (a camera's cam_rgb, cam_depth)
    "bytes": 5,
    "uint8_array": 5,
    "uint16_array": 5,
    "float32_array": 5,
}
RT_KEYS = ("rt_translation", "rt_rotation_euler_xyz")


def is_cortex_document(doc: Any) -> bool:
    return isinstance(doc, dict) and "DSRModel" in doc


def _id(value: Any) -> int | None:
    if isinstance(value, bool):
        return None
    if isinstance(value, int):
        return value
    if isinstance(value, str) and value.strip().isdigit():
        return int(value)
    return None


def _values(attributes: Any) -> dict[str, Any] | None:
    if not isinstance(attributes, dict):
        return None
    out = {}
    for name, spec in attributes.items():
        out[name] = spec.get("value") if isinstance(spec, dict) else spec
    return out


def from_cortex(
    doc: Any, vocabulary: Vocabulary | None = None, source: str = "cortex world"
) -> tuple[Graph, list[Violation]]:
    """Build a graph from a CORTEX document; every element it cannot accept is reported."""
    symbols = (
        doc.get("DSRModel", {}).get("symbols") if isinstance(doc.get("DSRModel"), dict) else None
    )
    if not isinstance(symbols, dict):
        raise FormatError(f"{source}: DSRModel.symbols must be an object of symbols")
    builder = WorldBuilder(vocabulary, source)
    links = []
    for key, symbol in symbols.items():
        at = f"{source}: symbol {key}"
        if not isinstance(symbol, dict):
            builder.report("malformed", f"symbol {key}", "must be an object", at)
            continue
        node_id = _id(symbol.get("id", key))
        if node_id is None or (_id(key) is not None and _id(key) != node_id):
            builder.report(
                "node-id",
                f"symbol {key}",
                f"id {symbol.get('id')!r} is not the integer id {key!r}",
                at,
            )
            continue
        attrs = _values(symbol.get("attribute", {}))
        if attrs is None:
            builder.report(
                "malformed", f"node {symbol.get('name')!r}", '"attribute" must be an object', at
            )
        builder.node(symbol.get("name"), symbol.get("type"), id=node_id, attrs=attrs or {}, at=at)
        for j, link in enumerate(symbol.get("links") or []):
            links.append((f"{at} links[{j}]", link))
    for at, link in links:
        if not isinstance(link, dict):
            builder.report("malformed", "link", "must be an object", at)
            continue
        src, dst, label = _id(link.get("src")), _id(link.get("dst")), link.get("label")
        if src is None or dst is None:
            builder.report(
                "malformed",
                f"edge {link.get('src')!r}->{link.get('dst')!r} ({label})",
                "src and dst must be integer ids",
                at,
            )
            continue
        element = builder.graph.describe_edge(src, dst, label)
        for end in (src, dst):
            if end not in builder.graph:
                builder.report("node-missing", element, f"node id {end} does not exist", at)
                break
        else:
            attrs = _values(link.get("linkAttribute") or {}) or {}
            rt = None
            if label == RT:
                missing = [k for k in RT_KEYS if k not in attrs]
                if missing:
                    builder.report(
                        "rt-rigid", element, f"an RT link needs {', '.join(missing)}", at
                    )
                    continue
                rt = units.scale_rt(
                    {
                        "translation": attrs.pop("rt_translation"),
                        "rotation_euler_xyz": attrs.pop("rt_rotation_euler_xyz"),
                    },
                    units.PER_METRE[units.LEGACY],
                )
            builder.edge(src, dst, label, attrs=attrs, rt=rt, at=at)
    return builder.finish(), builder.violations


def _attribute(graph: Graph, element: str, name: str, value: Any) -> dict[str, Any]:
    type_name = graph.vocabulary.attribute_type(name)
    code = TYPE_CODES.get(type_name)
    if code is None:
        raise FormatError(
            f"{element}: attribute {name!r} is {type_name}, which CORTEX files cannot hold"
        )
    if type_name == "uint64":
        value = str(value)
    elif is_binary(value):
        value = list(value if isinstance(value, bytes) else value.tobytes())
    return {"type": code, "value": value}


def to_cortex(graph: Graph) -> dict[str, Any]:
    """The graph as a CORTEX document (ids and link ends written as strings, as CORTEX does)."""
    symbols: dict[str, Any] = {}
    for node in sorted(graph.nodes(), key=lambda n: n.id):
        element = f"node {node.name!r}"
        links = []
        for edge in sorted(graph.out_edges(node.id), key=lambda e: (e.dst, e.type)):
            link_element = graph.describe_edge(*edge.key)
            link_attrs = {
                k: _attribute(graph, link_element, k, v) for k, v in sorted(edge.attrs.items())
            }
            if edge.rt is not None:
                link_attrs["rt_rotation_euler_xyz"] = {"type": 3, "value": rigid.euler_xyz(edge.rt)}
                link_attrs["rt_translation"] = {
                    "type": 3,
                    # to CORTEX's mm; rounded to a nanometre so 0.35 m is 350.0, not 349.99...
                    "value": [round(float(v) * units.PER_METRE["mm"], 6) for v in edge.rt[:3, 3]],
                }
            links.append(
                {
                    "dst": str(edge.dst),
                    "label": edge.type,
                    "linkAttribute": link_attrs,
                    "src": str(node.id),
                }
            )
        symbols[str(node.id)] = {
            "attribute": {
                k: _attribute(graph, element, k, v) for k, v in sorted(node.attrs.items())
            },
            "id": str(node.id),
            "links": links,
            "name": node.name,
            "type": node.type,
        }
    return {"DSRModel": {"symbols": symbols}}
