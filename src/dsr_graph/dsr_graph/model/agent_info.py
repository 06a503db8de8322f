"""Agents in the graph: every agent keeps a node of its own, its *agent info node* (CORTEX's
``agent`` node type), named after its fully qualified ROS name, saying who it is and whether it
is ready (docs/FORMAT.md, "Agents in the graph"). Pure logic: the agent runtime (ros/agent.py)
writes its own, the DSR server marks one gone when its process has ended, ``dsr agents`` lists
them, and a planner waits for the agents it needs.

An agent may always write its own info node, whatever the policy says (the server knows who
sent a request); no one else may, unless the policy lets them write ``agent`` nodes.
"""

from __future__ import annotations

from typing import Any

AGENT_TYPE = "agent"
STARTING, READY, GONE = "starting", "ready", "gone"
STATES = (STARTING, READY, GONE)  # "stopping" cannot be sent: see docs/FORMAT.md
# the attributes of an info node, as the agent itself writes them
ATTRIBUTES = frozenset(
    {"state", "pid", "host", "agent_run", "listens_to", "can_do", "started_at", "heartbeat"}
)


def info_ops(graph, name: str, attrs: dict[str, Any]) -> list[dict[str, Any]]:
    """The ops that make ``name``'s info node hold ``attrs`` (none when it already does)."""
    node = graph.find(name)
    if node is None:
        return [{"op": "insert_node", "name": name, "type": AGENT_TYPE, "attrs": dict(attrs)}]
    changed = {k: v for k, v in attrs.items() if node.attrs.get(k) != v}
    return [{"op": "set_node_attrs", "node": name, "attrs": changed}] if changed else []


def is_own_info(graph, agent: str, op: dict[str, Any]) -> bool:
    """``op`` writes only the info attributes of ``agent``'s own info node."""
    kind = op.get("op")
    names = set(op.get("attrs") or {}) | set(op.get("names") or [])
    if not names <= ATTRIBUTES:
        return False
    if kind == "insert_node":
        return op.get("name") == agent and op.get("type") == AGENT_TYPE
    if kind in ("set_node_attrs", "remove_node_attrs") and op.get("node") == agent:
        node = graph.find(agent)
        return node is not None and node.type == AGENT_TYPE
    return False


def gone_ops(graph, agents) -> list[dict[str, Any]]:
    """The ops marking these agents' info nodes gone (those not already so)."""
    ops = []
    for name in sorted(set(agents)):
        node = graph.find(name)
        if node is not None and node.type == AGENT_TYPE and node.attrs.get("state") != GONE:
            ops.append({"op": "set_node_attrs", "node": name, "attrs": {"state": GONE}})
    return ops


def listing(graph) -> list[dict[str, Any]]:
    """Every agent info node, as ``{"name", "state", ...its other attributes}``, by name."""
    agents = []
    for node in [n for n in graph.nodes() if n.type == AGENT_TYPE]:
        attrs = {k: v for k, v in node.attrs.items() if k in ATTRIBUTES}
        agents.append({"name": node.name, "state": attrs.pop("state", ""), **attrs})
    return sorted(agents, key=lambda a: a["name"])


def states(graph) -> dict[str, str]:
    """{agent name: its state} for every agent info node."""
    return {a["name"]: a["state"] for a in listing(graph)}
