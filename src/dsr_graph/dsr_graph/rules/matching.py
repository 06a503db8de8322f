"""Where a grammar pattern holds in a graph, and the same pattern as server-side preconditions
(so that a rule's "during" write is a compare-and-set). Pure."""

from __future__ import annotations

from collections.abc import Iterator
from typing import Any

from dsr_graph.model.graph import Graph
from dsr_graph.rules.syntax import WILDCARD, Bindings, Pattern, is_var, substitute


def _bind(term: Any, actual: Any, bindings: Bindings) -> Bindings | None:
    """Unify a pattern term with an actual value; the extended bindings or None."""
    if term == WILDCARD:
        return bindings
    if is_var(term):
        if term in bindings:
            return bindings if bindings[term] == actual else None
        return {**bindings, term: actual}
    return bindings if term == actual else None


def _attrs_match(
    pattern: dict[str, Any], attrs: dict[str, Any], bindings: Bindings
) -> Bindings | None:
    for name, term in pattern.items():
        if name not in attrs:
            return None
        bindings = _bind(term, attrs[name], bindings)
        if bindings is None:
            return None
    return bindings


def _resolve(term: Any, bindings: Bindings) -> str | None:
    """A node name if the term is a constant or a bound variable, else None."""
    if term == WILDCARD:
        return None
    if is_var(term):
        return bindings.get(term)
    return term


def _match_one(graph: Graph, p: Pattern, bindings: Bindings) -> Iterator[Bindings]:
    if p.kind == "node":
        name = _resolve(p.src, bindings)
        candidates = [graph.find(name)] if name is not None else list(graph.nodes())
        for node in candidates:
            if node is None or (p.type is not None and node.type != p.type):
                continue
            b = _bind(p.src, node.name, bindings)
            b = b if b is None else _attrs_match(p.attrs, node.attrs, b)
            if b is not None:
                yield b
        return
    src, dst = _resolve(p.src, bindings), _resolve(p.dst, bindings)
    if src is not None and dst is not None:
        edge = graph.edge(src, dst, p.type)
        edges = [edge] if edge is not None else []
    elif src is not None:
        edges = [e for e in graph.out_edges(src) if e.type == p.type] if src in graph else []
    elif dst is not None:
        edges = [e for e in graph.in_edges(dst) if e.type == p.type] if dst in graph else []
    else:
        edges = graph.edges_of_type(p.type)
    for edge in edges:
        b = _bind(p.src, graph.node(edge.src).name, bindings)
        b = b if b is None else _bind(p.dst, graph.node(edge.dst).name, b)
        b = b if b is None else _attrs_match(p.attrs, edge.attrs, b)
        if b is not None:
            yield b


def match(
    graph: Graph, patterns: list[Pattern], bindings: Bindings | None = None
) -> Iterator[Bindings]:
    """Every binding under which all patterns hold (positive patterns first, then negations)."""
    positive = [p for p in patterns if p.kind in ("edge", "node")]
    negative = [p for p in patterns if p.kind in ("no_edge", "no_node")]

    def holds(n: Pattern, b: Bindings) -> bool:
        as_positive = Pattern(
            "edge" if n.kind == "no_edge" else "node", n.src, n.dst, n.type, n.attrs
        )
        return any(True for _ in _match_one(graph, as_positive, b))

    def walk(i: int, b: Bindings) -> Iterator[Bindings]:
        if i == len(positive):
            if not any(holds(n, b) for n in negative):
                yield b
            return
        for extended in _match_one(graph, positive[i], b):
            yield from walk(i + 1, extended)

    yield from walk(0, dict(bindings or {}))


def preconditions(patterns: list[Pattern], bindings: Bindings) -> list[dict[str, Any]]:
    """The pattern as server-side checks, so the during write is a compare-and-set. Negations
    with a wildcard cannot be stated to the server and are checked locally only."""
    checks: list[dict[str, Any]] = []
    for p in patterns:
        if p.kind == "no_node":
            if p.src != WILDCARD:
                checks.append({"check": "node_absent", "node": substitute(p.src, bindings)})
            continue
        if p.kind == "node":
            name = substitute(p.src, bindings)
            checks.append({"check": "node_exists", "node": name})
            checks += [
                {"check": "attr_equals", "node": name, "attr": a, "value": substitute(v, bindings)}
                for a, v in p.attrs.items()
                if v != WILDCARD
            ]
            continue
        if WILDCARD in (p.src, p.dst):
            continue
        edge = {
            "from": substitute(p.src, bindings),
            "to": substitute(p.dst, bindings),
            "type": p.type,
        }
        checks.append({"check": "edge_exists" if p.kind == "edge" else "edge_absent", **edge})
        if p.kind == "edge":
            checks += [
                {"check": "attr_equals", **edge, "attr": a, "value": substitute(v, bindings)}
                for a, v in p.attrs.items()
                if v != WILDCARD
            ]
    return checks
