"""Build a graph element by element from a file, collecting every violation instead of stopping.

World files are written by people and by other programs (CORTEX): a loader must say precisely
everything it cannot accept. Elements that break a rule are left out and reported; the rest is
loaded, so a world with one bad edge is still usable (``dsr validate`` exits 1 on it).
"""

from __future__ import annotations

from typing import Any, List, Mapping, Optional

from dsr_graph.exceptions import RuleViolation, Violation
from dsr_graph.model.graph import Graph, NodeRef
from dsr_graph.model.vocabulary import Vocabulary


class WorldBuilder:
    def __init__(self, vocabulary: Optional[Vocabulary] = None, source: str = "world"):
        self.graph = Graph(vocabulary)
        self.source = source
        self.violations: List[Violation] = []

    def report(self, rule: str, element: str, message: str, at: Optional[str] = None) -> None:
        self.violations.append(Violation(rule, element, message, at or self.source))

    def node(self, name: Any, type: Any, id: Optional[int] = None,
             attrs: Optional[Mapping[str, Any]] = None, at: Optional[str] = None) -> bool:
        good = self._good_attrs(f"node {name!r}", attrs, at)
        return self._try(lambda: self.graph.insert_node(name, type, id=id, attrs=good), at)

    def edge(self, src: NodeRef, dst: NodeRef, type: Any,
             attrs: Optional[Mapping[str, Any]] = None, rt: Any = None, at: Optional[str] = None) -> bool:
        good = self._good_attrs(f"edge {src!r}->{dst!r} ({type})", attrs, at)
        return self._try(lambda: self.graph.insert_edge(src, dst, type, attrs=good, rt=rt), at)

    def _good_attrs(self, element: str, attrs: Optional[Mapping[str, Any]], at: Optional[str]) -> dict:
        """The attributes that pass the vocabulary; each bad one is reported and left out alone,
        so one odd attribute does not cost a node (and with it a whole RT subtree)."""
        if attrs is None:
            return {}
        if not isinstance(attrs, Mapping):
            self.report("malformed", element, f"attributes must be an object, got {type(attrs).__name__}", at)
            return {}
        good = {}
        for name, value in attrs.items():
            if self._try(lambda: self.graph.check_attribute(element, name, value), at):
                good[name] = value
        return good

    def finish(self) -> Graph:
        try:
            self.graph.check_single_tree()
        except RuleViolation as e:
            self.violations.append(e.violation.located(self.source))
        return self.graph

    def _try(self, action, at: Optional[str]) -> bool:
        try:
            action()
            return True
        except RuleViolation as e:
            self.violations.append(e.violation.located(at or self.source))
            return False
