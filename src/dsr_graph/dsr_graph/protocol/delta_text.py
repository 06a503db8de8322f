"""One-line, human-readable descriptions of ops and deltas (for `dsr watch`, logs, launch)."""

from __future__ import annotations

import json
from typing import Any

from dsr_graph.model.binary import short_text


def _attrs(attrs: dict[str, Any]) -> str:
    if not attrs:
        return ""
    return " {" + ", ".join(f"{k}={short_text(v)}" for k, v in attrs.items()) + "}"


def op_text(op: dict[str, Any]) -> str:
    kind = op["op"]
    if kind == "insert_node":
        return f"+node {op['name']}:{op['type']}{_attrs(op.get('attrs', {}))}"
    if kind == "delete_node":
        return f"-node {op['node']}"
    if kind == "set_node_attrs":
        return f"{op['node']}{_attrs(op['attrs'])}"
    if kind == "remove_node_attrs":
        return f"{op['node']} -attrs {','.join(op['names'])}"
    arrow = f"{op['from']} -{op.get('type', 'RT')}-> {op['to']}"
    if kind == "insert_edge":
        return f"+{arrow}{_attrs(op.get('attrs', {}))}"
    if kind == "delete_edge":
        return f"-{arrow}"
    if kind == "set_edge_attrs":
        return f"{arrow}{_attrs(op['attrs'])}"
    if kind == "remove_edge_attrs":
        return f"{arrow} -attrs {','.join(op['names'])}"
    if kind == "set_rt":
        t = [round(row[3], 3) for row in op["rt"]["matrix"][:3]]
        return f"{arrow} moved to {t}"
    return json.dumps(op)


def delta_text(delta: dict[str, Any]) -> str:
    parts = [op_text(op) for op in delta.get("ops", [])]
    claims = delta.get("claims", {})
    for c in claims.get("granted", []):
        parts.append(f"claim {json.dumps(c['target'])} p{c['priority']}")
    for c in claims.get("released", []):
        parts.append(f"release {json.dumps(c['target'])} of {c['agent']} ({c['reason']})")
    return f"seq {delta['seq']:>6}  {delta.get('agent') or '-':<20} " + "; ".join(parts)
