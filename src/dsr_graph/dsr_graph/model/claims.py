"""Claims: an agent reserves part of the graph with a priority while an action runs (the paper's
future work, Section V). Pure logic; the server owns the table and records every change in the
delta stream, so replicas (and the holder, when preempted) see the same table.

Targets (JSON):
  {"node": "person"}                              the node: its attributes, its deletion, its pose
  {"from": "robot", "to": "speaking"}             every edge from robot to speaking, any type
  {"from": "robot", "to": "speaking", "type": "is"}   that one edge

A write or claim that touches a target held by another agent goes through only with a strictly
higher priority, and then preempts the holder's claim. Claims end when released (explicitly,
typically by a rule's "after" write), when their lease expires, when the holder's ROS node is
gone, or when their node is deleted.
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass
from typing import Any

from dsr_graph.exceptions import TransactionRejected, Violation
from dsr_graph.model.graph import Graph
from dsr_graph.model.vocabulary import RT

TargetKey = tuple[str, ...]  # ("node", n) | ("pair", a, b) | ("edge", a, b, type)


def target_key(target: Any, at: str = "claim") -> TargetKey:
    """The key of a JSON target; ``TransactionRejected`` (malformed) when it is not one."""
    if isinstance(target, dict):
        keys = set(target)
        if keys == {"node"} and isinstance(target["node"], str):
            return ("node", target["node"])
        if keys in ({"from", "to"}, {"from", "to", "type"}) and all(
            isinstance(target[k], str) for k in keys
        ):
            if "type" in keys:
                return ("edge", target["from"], target["to"], target["type"])
            return ("pair", target["from"], target["to"])
    raise TransactionRejected(
        Violation(
            "malformed",
            at,
            'a claim target is {"node": name} or {"from", "to"[, "type"]} with names, '
            f"got {target!r}",
            at,
        )
    )


def target_json(key: TargetKey) -> dict[str, str]:
    if key[0] == "node":
        return {"node": key[1]}
    if key[0] == "pair":
        return {"from": key[1], "to": key[2]}
    return {"from": key[1], "to": key[2], "type": key[3]}


def target_text(key: TargetKey) -> str:
    if key[0] == "node":
        return f"node {key[1]!r}"
    if key[0] == "pair":
        return f"edges {key[1]!r}->{key[2]!r}"
    return f"edge {key[1]!r}->{key[2]!r} ({key[3]})"


@dataclass
class Claim:
    key: TargetKey
    agent: str
    priority: int
    expires: float | None = None  # absolute time (seconds since the epoch), None = no lease

    def to_json(self) -> dict[str, Any]:
        return {
            "target": target_json(self.key),
            "agent": self.agent,
            "priority": self.priority,
            "expires": self.expires,
        }

    @classmethod
    def from_json(cls, doc: dict[str, Any]) -> Claim:
        return cls(
            target_key(doc["target"]), doc["agent"], int(doc["priority"]), doc.get("expires")
        )


def touched(graph: Graph, op: dict[str, Any]) -> list[TargetKey]:
    """The claimable elements an op would change, resolved on the graph before it runs."""

    def name(ref: Any) -> Any:
        node = graph.find(ref)
        return node.name if node is not None else ref

    kind = op["op"]
    if kind in ("insert_node", "set_node_attrs", "remove_node_attrs", "delete_node"):
        n = name(op.get("node", op.get("name")))
        keys: list[TargetKey] = [("node", n)]
        if kind == "delete_node" and n in graph:
            for edge in graph.out_edges(n) + graph.in_edges(n):
                keys.append(
                    ("edge", graph.node(edge.src).name, graph.node(edge.dst).name, edge.type)
                )
        return keys
    a, b = name(op["from"]), name(op["to"])
    edge_type = op.get("type", RT)
    keys = [("edge", a, b, edge_type)]
    if edge_type == RT:
        keys.append(("node", b))  # an RT edge is the child's pose
    return keys


class ClaimTable:
    def __init__(self) -> None:
        self._claims: dict[TargetKey, Claim] = {}

    def __len__(self) -> int:
        return len(self._claims)

    def all(self) -> list[Claim]:
        return list(self._claims.values())

    def held_by(self, agent: str) -> list[Claim]:
        return [c for c in self._claims.values() if c.agent == agent]

    def covering(self, key: TargetKey) -> list[Claim]:
        """Claims that protect an element key (an edge is covered by its own claim and by its
        pair's)."""
        found = [self._claims[key]] if key in self._claims else []
        if key[0] == "edge" and ("pair", key[1], key[2]) in self._claims:
            found.append(self._claims[("pair", key[1], key[2])])
        if key[0] == "pair":
            found += [c for k, c in self._claims.items() if k[0] == "edge" and k[1:3] == key[1:3]]
        return found

    def check(self, agent: str, priority: int, keys: Iterable[TargetKey], at: str) -> list[Claim]:
        """Claims of others on ``keys`` that this request would preempt; ``TransactionRejected``
        (rule ``claimed``) if one of them has an equal or higher priority."""
        preempted: dict[TargetKey, Claim] = {}
        for key in keys:
            for claim in self.covering(key):
                if claim.agent == agent:
                    continue
                if priority <= claim.priority:
                    raise TransactionRejected(
                        Violation(
                            "claimed",
                            target_text(key),
                            f"claimed by {claim.agent!r} with priority {claim.priority} "
                            f"while its action runs; this request has priority {priority} "
                            "(a strictly higher one is needed)",
                            at,
                        )
                    )
                preempted[claim.key] = claim
        return list(preempted.values())

    # -- changes (the server computes them; everyone applies them from the delta) ---------------
    def apply_changes(self, changes: dict[str, Any]) -> None:
        for item in changes.get("released", []):
            key = target_key(item["target"])
            if key in self._claims and self._claims[key].agent == item["agent"]:
                del self._claims[key]
        for item in changes.get("granted", []):
            claim = Claim.from_json(item)
            self._claims[claim.key] = claim

    def expired(self, now: float) -> list[Claim]:
        return [c for c in self._claims.values() if c.expires is not None and c.expires <= now]

    def on_nodes(self, names: Iterable[str]) -> list[Claim]:
        gone = set(names)
        return [
            c
            for c in self._claims.values()
            if (c.key[0] == "node" and c.key[1] in gone)
            or (c.key[0] != "node" and (c.key[1] in gone or c.key[2] in gone))
        ]

    def to_json(self) -> list[dict[str, Any]]:
        return [c.to_json() for c in sorted(self._claims.values(), key=lambda c: c.key)]

    @classmethod
    def from_json(cls, items: list[dict[str, Any]]) -> ClaimTable:
        table = cls()
        for item in items:
            claim = Claim.from_json(item)
            table._claims[claim.key] = claim
        return table


def released(claim: Claim, reason: str, by: str = "") -> dict[str, Any]:
    """The delta record of a claim ending (reason: released, preempted, expired, agent-gone,
    node-deleted, unreachable)."""
    doc = {"target": target_json(claim.key), "agent": claim.agent, "reason": reason}
    if by:
        doc["by"] = by
    return doc
