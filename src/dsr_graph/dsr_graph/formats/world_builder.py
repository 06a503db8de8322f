"""Build a graph element by element from a file, collecting every violation instead of stopping.

World files are written by people and by other programs (CORTEX): a loader must say precisely
everything it cannot accept. Elements that break a rule are left out and reported; the rest is
loaded, so a world with one bad edge is still usable (``dsr validate`` exits 1 on it).
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from dsr_graph.exceptions import RuleViolation, Violation
from dsr_graph.model.graph import Graph, NodeRef
from dsr_graph.model.vocabulary import Vocabulary


class WorldBuilder:
    def __init__(self, vocabulary: Vocabulary | None = None, source: str = "world"):
        self.graph = Graph(vocabulary)
        self.source = source
        self.violations: list[Violation] = []

    def report(self, rule: str, element: str, message: str, at: str | None = None) -> None:
        self.violations.append(Violation(rule, element, message, at or self.source))

    def node(
        self,
        name: Any,
        type: Any,
        id: int | None = None,
        attrs: Mapping[str, Any] | None = None,
        at: str | None = None,
    ) -> bool:
        good = self._good_attrs(f"node {name!r}", attrs, at)
        return self._try(lambda: self.graph.insert_node(name, type, id=id, attrs=good), at)

    def edge(
        self,
        src: NodeRef,
        dst: NodeRef,
        type: Any,
        attrs: Mapping[str, Any] | None = None,
        rt: Any = None,
        at: str | None = None,
    ) -> bool:
        good = self._good_attrs(f"edge {src!r}->{dst!r} ({type})", attrs, at)
        return self._try(lambda: self.graph.insert_edge(src, dst, type, attrs=good, rt=rt), at)

    def _good_attrs(self, element: str, attrs: Mapping[str, Any] | None, at: str | None) -> dict:
        """The attributes that pass the vocabulary; each bad one is reported and left out alone,
        so one odd attribute does not cost a node (and with it a whole RT subtree)."""
        if attrs is None:
            return {}
        if not isinstance(attrs, Mapping):
            self.report(
                "malformed",
                element,
                f"attributes must be an object, got {type(attrs).__name__}",
                at,
            )
            return {}
        good = {}
        for name, value in attrs.items():
            check = lambda name=name, value=value: self.graph.check_attribute(element, name, value)  # noqa: E731
            if self._try(check, at):
                good[name] = value
        return good

    def finish(self) -> Graph:
        try:
            self.graph.check_single_tree()
        except RuleViolation as e:
            self.violations.append(e.violation.located(self.source))
        return self.graph

    def _try(self, action, at: str | None) -> bool:
        try:
            action()
            return True
        except RuleViolation as e:
            self.violations.append(e.violation.located(at or self.source))
            return False
