"""Which rules fire now (``search_for_changes`` of the paper's Algorithm 2) and the writes a
firing makes: its "during" with the "before" pattern as preconditions, its "after" by outcome.
Pure; ``runner`` drives it from an agent's changes."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from dsr_graph.model.graph import Graph
from dsr_graph.rules.matching import match, preconditions
from dsr_graph.rules.syntax import Bindings, Rule, substitute


@dataclass
class Firing:
    rule: Rule
    bindings: Bindings

    def during_tx(self) -> dict[str, Any]:
        tx: dict[str, Any] = {
            "preconditions": preconditions(self.rule.when, self.bindings),
            "ops": substitute(self.rule.during, self.bindings),
        }
        if self.rule.claim:
            tx["claim"] = substitute(self.rule.claim, self.bindings)
        return tx

    def after_tx(self, outcome: str, extra: Bindings | None = None) -> dict[str, Any] | None:
        """The after write for an outcome (None when the rule has none for it). It requires the
        during state to still hold: if something else undid it meanwhile, the after is refused."""
        bindings = {
            **self.bindings,
            **{(k if k.startswith("$") else "$" + k): v for k, v in (extra or {}).items()},
        }
        ops = self.rule.after.get(outcome)
        release = substitute(self.rule.claim, self.bindings) if self.rule.claim else []
        if ops is None:
            return {"ops": [], "release": release} if release else None
        held = [
            {"check": "edge_exists", "from": o["from"], "to": o["to"], "type": o["type"]}
            for o in substitute(self.rule.during, self.bindings)
            if o["op"] == "insert_edge"
        ]
        tx: dict[str, Any] = {"preconditions": held, "ops": substitute(ops, bindings)}
        if release:
            tx["release"] = release
        return tx


class GrammarEngine:
    """Which rules to fire now: search_for_changes of Algorithm 2, with the bookkeeping that
    keeps a rule from firing twice for the same situation."""

    def __init__(self, rules: list[Rule]):
        self.rules = rules
        self._busy: set = set()  # (rule name, key) sent or running
        self._last: dict[str, tuple] = {}  # rule name -> key of the last accepted firing (once_per)

    def search(self, graph: Graph) -> list[Firing]:
        firings = []
        for rule in self.rules:
            if rule.trigger is not None:
                continue  # percept rules fire on their event, see signal()
            for bindings in match(graph, rule.when):
                key = rule.key(bindings)
                if (rule.name, key) in self._busy:
                    continue
                if rule.once_per is not None and self._last.get(rule.name) == key:
                    continue
                firings.append(Firing(rule, bindings))
                if rule.once_per is not None:
                    break  # one firing per once_per rule and change
        return firings

    def signal(self, graph: Graph, event: str, values: dict[str, Any]) -> list[Firing]:
        """Percept rules triggered by ``event`` whose pattern holds, with the event's values bound
        (``values`` keys may omit the ``$``). Events are discrete: no once_per bookkeeping."""
        given = {(k if k.startswith("$") else "$" + k): v for k, v in values.items()}
        firings = []
        for rule in self.rules:
            if rule.trigger == event:
                for bindings in match(graph, rule.when, given):
                    firings.append(Firing(rule, bindings))
                    break
        return firings

    def started(self, firing: Firing) -> None:
        self._busy.add((firing.rule.name, firing.rule.key(firing.bindings)))

    def handled(self, firing: Firing) -> None:
        """The during write was answered (accepted, or refused because another agent acted):
        a once_per rule waits for its values to change before it fires again."""
        if firing.rule.once_per is not None:
            self._last[firing.rule.name] = firing.rule.key(firing.bindings)

    def finished(self, firing: Firing) -> None:
        self._busy.discard((firing.rule.name, firing.rule.key(firing.bindings)))
