"""Who may write what in the DSR, and with which claim priority (the paper's future work:
"access to specific parts of the DSR" with "priority levels"). Pure logic; the server loads it
from its ``policy_file`` (YAML) and checks every request against it before applying it.

    version: 1
    agents:                      # the first entry whose name matches the sender wins
      - name: /pelea             # a fully qualified node name, or a pattern (fnmatch: /clarc_*)
        priority: 10             # its claims' priority (a request's own "priority" is ignored)
        nodes: [test_item]       # node types it may insert or delete ("*": any)
        edges: [is_in, RT]       # edge types it may insert or delete (RT: also move, set_rt)
        attributes: [item, text] # attribute names it may set or remove, on nodes or on edges
      - name: "*"                # everyone else (without such an entry, the rest may not write)
        priority: 0

A list left out means nothing of that kind. Deleting a node takes its edges with it (the node
type is what is checked). Writing attributes of an edge needs both its type and the names.
Whatever the policy, an agent may write its own agent info node (model/agent_info.py).
Without a policy every agent may write anything, all with the same priority, so no one preempts
anyone (``OPEN``).
"""

from __future__ import annotations

import fnmatch
from dataclasses import dataclass
from typing import Any

from dsr_graph.exceptions import FormatError, TransactionRejected, Violation
from dsr_graph.model.agent_info import is_own_info
from dsr_graph.model.graph import Graph
from dsr_graph.model.vocabulary import RT

VERSION = 1
ANY = "*"
SOME = "(some type)"  # claiming the edges of a pair that has none yet: any edge type allowed
RULE_KEYS = {"name", "priority", "nodes", "edges", "attributes"}


@dataclass(frozen=True)
class AgentRule:
    name: str  # pattern on the fully qualified node name
    priority: int = 0
    nodes: frozenset[str] = frozenset()
    edges: frozenset[str] = frozenset()
    attributes: frozenset[str] = frozenset()

    def may(self, kind: str, what: str) -> bool:
        allowed = getattr(self, kind)
        return ANY in allowed or what in allowed or (what == SOME and bool(allowed))


class Policy:
    def __init__(self, rules: list[AgentRule], source: str = "policy"):
        self.rules = rules
        self.source = source

    @property
    def is_open(self) -> bool:
        return self is OPEN

    def rule_for(self, agent: str) -> AgentRule | None:
        for rule in self.rules:
            if fnmatch.fnmatchcase(agent, rule.name):
                return rule
        return None

    def priority_of(self, agent: str) -> int:
        rule = self.rule_for(agent)
        return rule.priority if rule is not None else 0

    # ------------------------------------------------------------------ checking
    def check(self, graph: Graph, agent: str, ops: list[dict[str, Any]]) -> None:
        """``TransactionRejected`` (rule ``policy``) naming the agent, the op and the rule, for
        the first op the agent may not do; ops are checked on the graph before they run."""
        if self is OPEN:
            return
        rule = self.rule_for(agent)
        for i, op, kind, what in _writes(graph, ops):
            if is_own_info(graph, agent, op):  # every agent describes itself (agent_info.py)
                continue
            at = f"op {i} ({op.get('op')})"
            if rule is None:
                _refuse(agent, at, f"no entry of {self.source} names {agent!r}")
            if not rule.may(kind, what):
                _refuse(
                    agent,
                    at,
                    f"{agent!r} may not write {_KIND_TEXT[kind]} {what!r} "
                    f"({self.source}: entry {rule.name!r} allows {_allowed(rule, kind)})",
                )

    def check_claims(self, graph: Graph, agent: str, targets: list[Any]) -> None:
        """An agent may claim only what it may write: a node whose type it may write (insert
        or delete), an edge whose type it may write, every edge between two nodes only when it
        may write each type joining them now (and some edge type at all). ``TransactionRejected``
        (rule ``policy``) for the first target it may not claim; malformed targets are left to
        the claims' own check."""
        if self is OPEN:
            return
        rule = self.rule_for(agent)
        for i, target in enumerate(targets):
            at = f"claim {i}"
            if not isinstance(target, dict):
                continue
            if rule is None:
                _refuse(agent, at, f"no entry of {self.source} names {agent!r}")
            for kind, what in _claimed(graph, target):
                if not rule.may(kind, what):
                    _refuse(
                        agent,
                        at,
                        f"{agent!r} may not claim {_KIND_TEXT[kind]} {what!r}: it may not write "
                        f"it ({self.source}: entry {rule.name!r} allows {_allowed(rule, kind)})",
                    )

    # ------------------------------------------------------------------ loading
    @classmethod
    def from_doc(cls, doc: Any, source: str = "policy") -> Policy:
        if not isinstance(doc, dict) or set(doc) - {"version", "agents"}:
            raise FormatError(f'{source}: the top level is {{"version": 1, "agents": [...]}}')
        if doc.get("version") != VERSION:
            raise FormatError(f"{source}: version must be {VERSION}, got {doc.get('version')!r}")
        entries = doc.get("agents")
        if not isinstance(entries, list) or not entries:
            raise FormatError(f'{source}: "agents" must be a non-empty list')
        rules = [_rule(entry, f"{source}: agents[{i}]") for i, entry in enumerate(entries)]
        return cls(rules, source)

    @classmethod
    def load(cls, path: str) -> Policy:
        import yaml

        try:
            with open(path, encoding="utf-8") as f:
                doc = yaml.safe_load(f)
        except OSError as e:
            raise FormatError(f"cannot read the policy file {path}: {e.strerror}") from None
        except yaml.YAMLError as e:
            raise FormatError(f"{path} is not YAML: {e}") from None
        return cls.from_doc(doc, path)


OPEN = Policy([AgentRule(ANY, 0, frozenset({ANY}), frozenset({ANY}), frozenset({ANY}))], "open")

_KIND_TEXT = {"nodes": "node type", "edges": "edge type", "attributes": "attribute"}


def _needs(graph: Graph, op: dict[str, Any], inserted: dict[str, str]) -> list[tuple[str, str]]:
    """What an op writes, as (kind, name) pairs the agent's rule must allow."""
    kind = op.get("op")
    attrs = list(op.get("attrs") or {}) + list(op.get("names") or [])
    if kind == "insert_node":
        return [("nodes", op.get("type"))] + [("attributes", a) for a in attrs]
    if kind == "delete_node":
        ref = op.get("node")
        node = graph.find(ref)
        node_type = node.type if node is not None else inserted.get(ref)
        return [("nodes", node_type)] if node_type is not None else []
    if kind in ("set_node_attrs", "remove_node_attrs"):
        return [("attributes", a) for a in attrs]
    if kind == "set_rt":
        return [("edges", RT)]
    if kind == "delete_edge":  # (a delta's copy of it also lists the attributes that went)
        return [("edges", op.get("type"))]
    if kind in ("insert_edge", "set_edge_attrs", "remove_edge_attrs"):
        return [("edges", op.get("type"))] + [("attributes", a) for a in attrs]
    return []  # malformed: the transaction's own checks name it


def observe_writes(seen: dict[str, dict[str, set[str]]], graph: Graph, delta: dict[str, Any]):
    """Add what an accepted delta's agent wrote to ``seen`` ({agent: {"nodes": types, "edges":
    types, "attributes": names}}), then apply the delta to ``graph``: the same reading of ops as
    ``Policy.check``, so a policy drafted from ``seen`` allows exactly what was written."""
    from dsr_graph.model.transaction import apply_ops

    mine = seen.setdefault(delta.get("agent", ""), {k: set() for k in _KIND_TEXT})
    ops = delta.get("ops", [])
    for _i, op, kind, what in _writes(graph, ops):
        if not is_own_info(graph, delta.get("agent", ""), op):  # allowed to all (check)
            mine[kind].add(what)
    apply_ops(graph, ops)


def _claimed(graph: Graph, target: dict[str, Any]) -> list[tuple[str, str]]:
    """What a claim target covers, as (kind, name) pairs the claimer's rule must allow."""
    if set(target) == {"node"}:
        node = graph.find(target["node"]) if isinstance(target["node"], str) else None
        return [("nodes", node.type)] if node is not None else []
    if "type" in target:
        return [("edges", target["type"])] if isinstance(target["type"], str) else []
    src, dst = target.get("from"), target.get("to")
    if not (isinstance(src, str) and isinstance(dst, str)):
        return []
    a, b = graph.find(src), graph.find(dst)
    joining = {e.type for e in graph.out_edges(a.id) if e.dst == b.id} if a and b else set()
    return [("edges", t) for t in sorted(joining)] or [("edges", SOME)]


def _writes(graph: Graph, ops: list[dict[str, Any]]):
    """(op index, op, kind, name) for everything the ops write, read on ``graph`` before they
    run; a node inserted earlier in the same ops is known by its type."""
    inserted: dict[str, str] = {}
    for i, op in enumerate(ops):
        for kind, what in _needs(graph, op, inserted):
            yield i, op, kind, what
        if op.get("op") == "insert_node":
            inserted[op.get("name")] = op.get("type")


def _refuse(agent: str, at: str, message: str) -> None:
    raise TransactionRejected(Violation("policy", f"agent {agent!r}", message, at))


def _allowed(rule: AgentRule, kind: str) -> str:
    allowed = sorted(getattr(rule, kind))
    return "any" if ANY in allowed else (", ".join(allowed) or "none")


def _rule(entry: Any, at: str) -> AgentRule:
    if not isinstance(entry, dict) or not isinstance(entry.get("name"), str):
        raise FormatError(f'{at}: an entry needs "name" (a node name or pattern)')
    unknown = set(entry) - RULE_KEYS
    if unknown:
        raise FormatError(f"{at}: unknown keys {sorted(unknown)} (known: {sorted(RULE_KEYS)})")
    priority = entry.get("priority", 0)
    if isinstance(priority, bool) or not isinstance(priority, int):
        raise FormatError(f"{at}: priority must be an integer, got {priority!r}")
    lists = {}
    for kind in ("nodes", "edges", "attributes"):
        value = entry.get(kind, [])
        if not isinstance(value, list) or not all(isinstance(v, str) for v in value):
            raise FormatError(f"{at}: {kind} must be a list of names, got {value!r}")
        lists[kind] = frozenset(value)
    return AgentRule(entry["name"], priority, **lists)
