"""Transactions: an ordered list of operations applied all-or-nothing, guarded by preconditions.

The preconditions are checked on the state before the first operation, so a grammar rule's
"before" pattern and its "during" write happen atomically (compare-and-set). The JSON shapes
are documented in docs/FORMAT.md.

``apply_transaction`` returns the *canonical* operations: node references as names, assigned
ids filled in, attribute values coerced, transforms as matrices. Replaying the canonical
operations on an equal graph gives an equal graph; that is what replicas do with deltas.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from typing import Any

from dsr_graph.exceptions import RuleViolation, TransactionRejected, ValueTypeError, Violation
from dsr_graph.model import binary, rigid
from dsr_graph.model.graph import Edge, Graph, Node, NodeRef
from dsr_graph.model.values import coerce

FORMAT = "dsr-graph"
VERSION = 1

EDGE_KEYS = ("from", "to", "type")

# op name -> (required keys, optional keys)
OP_SHAPES: dict[str, tuple[tuple[str, ...], tuple[str, ...]]] = {
    "insert_node": (("name", "type"), ("id", "attrs")),
    "delete_node": (("node",), ()),
    "set_node_attrs": (("node", "attrs"), ()),
    "remove_node_attrs": (("node", "names"), ()),
    "insert_edge": (EDGE_KEYS, ("attrs", "rt")),
    "delete_edge": (EDGE_KEYS, ()),
    "set_edge_attrs": (EDGE_KEYS + ("attrs",), ()),
    "remove_edge_attrs": (EDGE_KEYS + ("names",), ()),
    "set_rt": (("from", "to", "rt"), ()),
}

CHECK_SHAPES: dict[str, tuple[tuple[str, ...], tuple[str, ...]]] = {
    "node_exists": (("node",), ()),
    "node_absent": (("node",), ()),
    "edge_exists": (EDGE_KEYS, ()),
    "edge_absent": (EDGE_KEYS, ()),
    # attr_equals / version_equals address a node ("node") or an edge ("from", "to", "type").
    "attr_equals": (("attr", "value"), ("node",) + EDGE_KEYS),
    "version_equals": (("version",), ("node",) + EDGE_KEYS),
}

# What each key must hold (JSON types); node references are a name (string) or an id (integer).
_REF = "a node name (string) or id (integer)"
KEY_TYPES: dict[str, tuple[Callable[[Any], bool], str]] = {
    "name": (lambda v: isinstance(v, str), "a string"),
    "type": (lambda v: isinstance(v, str), "a string"),
    "attr": (lambda v: isinstance(v, str), "a string"),
    "node": (lambda v: isinstance(v, (str, int)) and not isinstance(v, bool), _REF),
    "from": (lambda v: isinstance(v, (str, int)) and not isinstance(v, bool), _REF),
    "to": (lambda v: isinstance(v, (str, int)) and not isinstance(v, bool), _REF),
    "id": (lambda v: isinstance(v, int) and not isinstance(v, bool), "an integer"),
    "version": (lambda v: isinstance(v, int) and not isinstance(v, bool), "an integer"),
    "attrs": (lambda v: isinstance(v, dict), "an object"),
    "rt": (lambda v: isinstance(v, dict), "an object"),
    "names": (
        lambda v: isinstance(v, list) and all(isinstance(n, str) for n in v),
        "a list of strings",
    ),
}

TRANSACTION_KEYS = {
    "format",
    "version",
    "kind",
    "id",
    "agent",
    "priority",
    "preconditions",
    "ops",
    "claim",
    "release",
    "lease",
}


@dataclass
class Transaction:
    """A parsed, structurally valid transaction request."""

    ops: list[dict[str, Any]]
    preconditions: list[dict[str, Any]] = field(default_factory=list)
    id: str = ""
    agent: str = ""
    priority: int = 0
    claim: list[dict[str, Any]] = field(default_factory=list)  # targets, see claims.py
    release: Any = field(default_factory=list)  # targets, or "all"
    lease: float | None = None  # seconds a claim lasts unless released earlier

    def to_json(self) -> dict:
        doc: dict[str, Any] = {"format": FORMAT, "version": VERSION, "kind": "transaction"}
        if self.id:
            doc["id"] = self.id
        if self.agent:
            doc["agent"] = self.agent
        if self.priority:
            doc["priority"] = self.priority
        if self.preconditions:
            doc["preconditions"] = self.preconditions
        doc["ops"] = self.ops
        if self.claim:
            doc["claim"] = self.claim
        if self.release:
            doc["release"] = self.release
        if self.lease is not None:
            doc["lease"] = self.lease
        return doc


def _reject(rule: str, element: str, message: str, at: str | None = None) -> None:
    raise TransactionRejected(Violation(rule, element, message, at))


def _check_shape(
    item: Any, kind_key: str, shapes: Mapping[str, tuple[tuple[str, ...], tuple[str, ...]]], at: str
) -> dict[str, Any]:
    if not isinstance(item, dict):
        _reject("malformed", at, f"must be an object, got {type(item).__name__}", at)
    kind = item.get(kind_key)
    if not isinstance(kind, str) or kind not in shapes:
        _reject("malformed", at, f"unknown {kind_key} {kind!r}; known: {', '.join(shapes)}", at)
    required, optional = shapes[kind]
    missing = [k for k in required if k not in item]
    if missing:
        _reject("malformed", at, f"{kind} needs {', '.join(missing)}", at)
    extra = set(item) - set(required) - set(optional) - {kind_key}
    if extra:
        _reject("malformed", at, f"{kind} does not take {', '.join(sorted(extra))}", at)
    for key, value in item.items():
        if key in KEY_TYPES and not KEY_TYPES[key][0](value):
            _reject("malformed", at, f'"{key}" must be {KEY_TYPES[key][1]}, got {value!r}', at)
    return item


def parse_transaction(doc: Any) -> Transaction:
    """Check the structure of a transaction document; ``TransactionRejected`` names what is
    wrong."""
    if not isinstance(doc, dict):
        _reject("malformed", "transaction", f"must be a JSON object, got {type(doc).__name__}")
    unknown = set(doc) - TRANSACTION_KEYS
    if unknown:
        _reject("malformed", "transaction", f"unknown keys {sorted(unknown)}")
    if doc.get("format", FORMAT) != FORMAT:
        _reject(
            "malformed", "transaction", f'"format" must be "{FORMAT}", got {doc.get("format")!r}'
        )
    if doc.get("version", VERSION) != VERSION:
        _reject(
            "unsupported-version",
            "transaction",
            f"version {doc.get('version')!r} is not supported (this is {VERSION})",
        )
    if doc.get("kind", "transaction") != "transaction":
        _reject(
            "malformed", "transaction", f'"kind" must be "transaction", got {doc.get("kind")!r}'
        )
    for key in ("id", "agent"):
        if not isinstance(doc.get(key, ""), str):
            _reject("malformed", "transaction", f'"{key}" must be a string')
    priority = doc.get("priority", 0)
    if isinstance(priority, bool) or not isinstance(priority, int):
        _reject("malformed", "transaction", '"priority" must be an integer')
    claim, release, lease = doc.get("claim", []), doc.get("release", []), doc.get("lease")
    if not isinstance(claim, list) or not (release == "all" or isinstance(release, list)):
        _reject(
            "malformed",
            "transaction",
            '"claim" must be a list of targets; "release" a list or "all"',
        )
    if lease is not None and (
        isinstance(lease, bool) or not isinstance(lease, (int, float)) or not lease > 0
    ):
        _reject("malformed", "transaction", '"lease" must be a positive number of seconds')
    if (claim or release) and not doc.get("agent"):
        _reject(
            "malformed", "transaction", 'claims need "agent": the ROS node name that holds them'
        )
    ops = doc.get("ops", [])
    if not isinstance(ops, list) or not (ops or claim or release):
        _reject("malformed", "transaction", '"ops" must be a non-empty list of operations')
    checks = doc.get("preconditions", [])
    if not isinstance(checks, list):
        _reject("malformed", "transaction", '"preconditions" must be a list')
    return Transaction(
        ops=[_check_shape(op, "op", OP_SHAPES, f"op {i}") for i, op in enumerate(ops)],
        preconditions=[
            _check_shape(c, "check", CHECK_SHAPES, f"precondition {i}")
            for i, c in enumerate(checks)
        ],
        id=doc.get("id", ""),
        agent=doc.get("agent", ""),
        priority=priority,
        claim=claim,
        release=release,
        lease=None if lease is None else float(lease),
    )


# ---------------------------------------------------------------------------- preconditions
def _edge_label(check: Mapping[str, Any]) -> str:
    return f"edge {check.get('from')!r}->{check.get('to')!r} ({check.get('type')})"


def _addressed(graph: Graph, check: Mapping[str, Any], at: str) -> tuple[str, object | None]:
    """The element an attr_equals/version_equals check talks about: a node or an edge."""
    has_node = "node" in check
    has_edge = [k in check for k in EDGE_KEYS]
    if has_node == any(has_edge) or (any(has_edge) and not all(has_edge)):
        _reject(
            "malformed", at, 'address either a node ("node") or an edge ("from", "to", "type")', at
        )
    if has_node:
        node = graph.find(check["node"])
        return f"node {check['node']!r}", node
    return _edge_label(check), graph.edge(check["from"], check["to"], check["type"])


def check_preconditions(graph: Graph, checks: list[dict[str, Any]]) -> None:
    """Raise ``TransactionRejected`` (rule ``precondition``) at the first check that does not
    hold."""
    for i, check in enumerate(checks):
        at = f"precondition {i} ({check['check']})"
        kind = check["check"]
        if kind in ("node_exists", "node_absent"):
            exists = graph.find(check["node"]) is not None
            if exists != (kind == "node_exists"):
                _reject(
                    "precondition",
                    f"node {check['node']!r}",
                    "expected to exist" if kind == "node_exists" else "expected not to exist",
                    at,
                )
        elif kind in ("edge_exists", "edge_absent"):
            exists = graph.edge(check["from"], check["to"], check["type"]) is not None
            if exists != (kind == "edge_exists"):
                _reject(
                    "precondition",
                    _edge_label(check),
                    "expected to exist" if kind == "edge_exists" else "expected not to exist",
                    at,
                )
        elif kind == "attr_equals":
            label, element = _addressed(graph, check, at)
            if element is None:
                _reject("precondition", label, "does not exist", at)
            actual = element.attrs.get(check["attr"], _MISSING)
            expected = check["value"]
            if binary.is_binary(actual):  # given as JSON: read as the attribute's type
                try:
                    expected = coerce(graph.vocabulary.attribute_type(check["attr"]), expected)
                except ValueTypeError:
                    expected = None
            if actual is _MISSING or not _equal(actual, expected):
                shown = "absent" if actual is _MISSING else _shown(actual)
                _reject(
                    "precondition",
                    label,
                    f"expected {check['attr']} == {_shown(check['value'])}, found {shown}",
                    at,
                )
        elif kind == "version_equals":
            label, element = _addressed(graph, check, at)
            if element is None:
                _reject("precondition", label, "does not exist", at)
            if element.version != check["version"]:
                _reject(
                    "precondition",
                    label,
                    f"expected version {check['version']!r}, found {element.version}",
                    at,
                )


_MISSING = object()


def _shown(value: Any) -> str:
    """A value as a rejection names it: a binary one by its size, not its bytes."""
    size = binary.declared_size(value)
    if size or binary.is_binary(value):
        return f"a binary value of {size} bytes"
    return repr(value)


def _equal(actual: Any, expected: Any) -> bool:
    # Stored values are canonical (floats widened); compare numbers by value, not by JSON type.
    if isinstance(actual, bool) or isinstance(expected, bool):
        return type(actual) is type(expected) and actual == expected
    return binary.equal(actual, expected)


# ---------------------------------------------------------------------------- operations
def _ref(value: Any) -> NodeRef:
    return value  # names are str, ids are int; the graph tells them apart by type


def _edge_op(kind: str, edge: Edge, graph: Graph, **extra: Any) -> dict[str, Any]:
    op = {
        "op": kind,
        "from": graph.node(edge.src).name,
        "to": graph.node(edge.dst).name,
        "type": edge.type,
    }
    op.update(extra)
    return op


def _insert_node(graph: Graph, op: Mapping[str, Any]) -> dict[str, Any]:
    node = graph.insert_node(op["name"], op["type"], id=op.get("id"), attrs=op.get("attrs"))
    return {
        "op": "insert_node",
        "id": node.id,
        "name": node.name,
        "type": node.type,
        "attrs": dict(node.attrs),
    }


def _delete_node(graph: Graph, op: Mapping[str, Any]) -> dict[str, Any]:
    node = graph.find(op["node"])
    name = node.name if node is not None else op["node"]
    graph.delete_node(op["node"])
    return {"op": "delete_node", "node": name}


def _set_node_attrs(graph: Graph, op: Mapping[str, Any]) -> dict[str, Any]:
    node: Node = graph.set_node_attrs(op["node"], op["attrs"])
    return {
        "op": "set_node_attrs",
        "node": node.name,
        "attrs": {k: node.attrs[k] for k in op["attrs"]},
    }


def _remove_node_attrs(graph: Graph, op: Mapping[str, Any]) -> dict[str, Any]:
    node = graph.remove_node_attrs(op["node"], op["names"])
    return {"op": "remove_node_attrs", "node": node.name, "names": list(op["names"])}


def _insert_edge(graph: Graph, op: Mapping[str, Any]) -> dict[str, Any]:
    edge = graph.insert_edge(
        op["from"], op["to"], op["type"], attrs=op.get("attrs"), rt=op.get("rt")
    )
    canonical = _edge_op("insert_edge", edge, graph, attrs=dict(edge.attrs))
    if edge.rt is not None:
        canonical["rt"] = rigid.to_json(edge.rt)
    return canonical


def _delete_edge(graph: Graph, op: Mapping[str, Any]) -> dict[str, Any]:
    edge = graph.edge(op["from"], op["to"], op["type"])
    graph.delete_edge(op["from"], op["to"], op["type"])
    return _edge_op("delete_edge", edge, graph)


def _set_edge_attrs(graph: Graph, op: Mapping[str, Any]) -> dict[str, Any]:
    edge = graph.set_edge_attrs(op["from"], op["to"], op["type"], op["attrs"])
    return _edge_op("set_edge_attrs", edge, graph, attrs={k: edge.attrs[k] for k in op["attrs"]})


def _remove_edge_attrs(graph: Graph, op: Mapping[str, Any]) -> dict[str, Any]:
    edge = graph.remove_edge_attrs(op["from"], op["to"], op["type"], op["names"])
    return _edge_op("remove_edge_attrs", edge, graph, names=list(op["names"]))


def _set_rt(graph: Graph, op: Mapping[str, Any]) -> dict[str, Any]:
    edge = graph.set_rt(op["from"], op["to"], op["rt"])
    canonical = _edge_op("set_rt", edge, graph, rt=rigid.to_json(edge.rt))
    del canonical["type"]
    return canonical


APPLY: dict[str, Callable[[Graph, Mapping[str, Any]], dict[str, Any]]] = {
    "insert_node": _insert_node,
    "delete_node": _delete_node,
    "set_node_attrs": _set_node_attrs,
    "remove_node_attrs": _remove_node_attrs,
    "insert_edge": _insert_edge,
    "delete_edge": _delete_edge,
    "set_edge_attrs": _set_edge_attrs,
    "remove_edge_attrs": _remove_edge_attrs,
    "set_rt": _set_rt,
}
assert set(APPLY) == set(OP_SHAPES)


def apply_op(graph: Graph, op: Mapping[str, Any]) -> dict[str, Any]:
    """Apply one structurally valid op (no atomicity of its own); return its canonical form."""
    return APPLY[op["op"]](graph, op)


def apply_ops(
    graph: Graph, ops: list[dict[str, Any]], preconditions: list[dict[str, Any]] | None = None
) -> list[dict[str, Any]]:
    """Check the preconditions, then apply every op, all or nothing. Returns the canonical ops;
    raises ``TransactionRejected`` (graph unchanged) naming the op, the element and the rule."""
    check_preconditions(graph, preconditions or [])
    canonical: list[dict[str, Any]] = []
    try:
        with graph.atomic():
            for i, op in enumerate(ops):
                try:
                    canonical.append(apply_op(graph, op))
                except RuleViolation as e:
                    raise TransactionRejected(e.violation.located(f"op {i} ({op['op']})")) from e
    except TransactionRejected:
        raise
    except RuleViolation as e:  # end-of-transaction rules (rt-single-tree)
        raise TransactionRejected(e.violation.located("end of transaction")) from e
    return canonical


def apply_transaction(graph: Graph, doc: Any) -> tuple[Transaction, list[dict[str, Any]]]:
    """Parse and apply a transaction document. Returns it parsed and its canonical ops."""
    tx = parse_transaction(doc)
    return tx, apply_ops(graph, tx.ops, tx.preconditions)
