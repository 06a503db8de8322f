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
LISTS = ("listens_to", "can_do")  # strings of comma-separated items (CORTEX has no string lists)
ATTRIBUTES = frozenset({"state", "pid", "host", "agent_run", "listens_to", "can_do", "started_at"})


def joined(items) -> str:
    """A list attribute's value: its items, separated by commas."""
    return ", ".join(items)


def split(value: Any) -> list[str]:
    """A list attribute's items (none for a value that is not a string)."""
    return (
        [item.strip() for item in value.split(",") if item.strip()]
        if isinstance(value, str)
        else []
    )


def info_ops(graph, name: str, attrs: dict[str, Any]) -> list[dict[str, Any]]:
    """The ops that make ``name``'s info node hold ``attrs`` (none when it already does); the
    values of ``LISTS`` may be given as lists."""
    attrs = {k: joined(v) if k in LISTS and not isinstance(v, str) else v for k, v in attrs.items()}
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


def run_of(request_id: str, agent: str) -> str | None:
    """The run a request id names, when it is one of the agent runtime's
    (``<agent>:<run>:<count>``, protocol/agent_core.py) sent by ``agent``; else None."""
    parts = request_id.rsplit(":", 2) if isinstance(request_id, str) else []
    if len(parts) != 3 or parts[0] != agent or not parts[1] or not parts[2].isdigit():
        return None
    return parts[1]


def ended_run(graph, agent: str, request_id: str) -> bool:
    """``agent``'s info node shows a run other than the one ``request_id`` names, and not gone:
    the process that wrote it has ended (the server lets no live twin of a name write)."""
    run = run_of(request_id, agent)
    node = graph.find(agent) if run is not None else None
    if node is None or node.type != AGENT_TYPE or node.attrs.get("state") == GONE:
        return False
    return node.attrs.get("agent_run") not in (None, run)


def gone_ops(graph, agents) -> list[dict[str, Any]]:
    """The ops marking these agents' info nodes gone (those not already so)."""
    ops = []
    for name in sorted(set(agents)):
        node = graph.find(name)
        if node is not None and node.type == AGENT_TYPE and node.attrs.get("state") != GONE:
            ops.append({"op": "set_node_attrs", "node": name, "attrs": {"state": GONE}})
    return ops


def listing(graph) -> list[dict[str, Any]]:
    """Every agent info node, as ``{"name", "state", ...its other attributes}`` (``LISTS`` as
    lists), by name."""
    agents = []
    for node in [n for n in graph.nodes() if n.type == AGENT_TYPE]:
        attrs = {k: v for k, v in node.attrs.items() if k in ATTRIBUTES}
        attrs |= {k: split(attrs[k]) for k in LISTS if k in attrs}
        agents.append({"name": node.name, "state": attrs.pop("state", ""), **attrs})
    return sorted(agents, key=lambda a: a["name"])


def missing_abilities(graph, needed, away=frozenset()) -> list[str]:
    """The abilities in ``needed`` that no ``ready`` agent offers (``can_do``), those ``away``
    (out of the server's reach: killed a moment ago, or cut off) not counted. None missing
    when the graph describes no agent at all: a DSR whose agents do not describe themselves
    (an in-process test bus, an older agent set) is taken as it was before agents did."""
    agents = listing(graph)
    if not agents:
        return []
    offered = {
        ability
        for agent in agents
        if agent["state"] == READY and agent["name"] not in away
        for ability in agent.get("can_do", [])
    }
    return [a for a in needed if a not in offered]


def states(graph) -> dict[str, str]:
    """{agent name: its state} for every agent info node."""
    return {a["name"]: a["state"] for a in listing(graph)}
