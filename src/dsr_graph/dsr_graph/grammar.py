"""Grammar rules declared as data (paper, Fig. 3 and Algorithm 2): a *before* pattern, the
*during* write, the process to run, and the *after* write. Pure logic; ``rule_agent.py`` runs
the rules in a ROS node.

A rule (JSON or YAML):

    name: start_speaking
    when:                                  # the "before" pattern; every line must hold
      - edge: [robot, speaking, is_not]
      - edge: [test, test_part, is_in]
        attrs: {text: $text, sentence_id: $sid}    # $names bind values (or nodes)
      - no_edge: [person, robot, lost]     # must NOT hold
      - node: $p                           # a node, optionally by type and attributes
        type: person
    once_per: [$sid]                       # fire again only when these values change
    during:                                # sent with `when` as its preconditions (CAS):
      - delete_edge: [robot, speaking, is_not]      # two agents never both take the action
      - insert_edge: [robot, speaking, is]
    claim: [{from: robot, to: speaking}]   # held while the process runs (optional)
    priority: 1
    process: say                           # the agent's process, called with the bindings
    after:                                 # by outcome of the process (a list means "done")
      done:
        - delete_edge: [robot, speaking, is]
        - insert_edge: [robot, speaking, finish]

A *percept rule* has ``trigger: <event>`` (and ``given: [$vars]`` the event brings): it fires when
the agent signals that event (a face seen, a tap on the screen) and its ``when`` holds; this is
how sensor data enters the graph with the same compare-and-set safety. ``no_node: name`` is a
negated node pattern.

Op shorthands: insert_edge/delete_edge: [from, to, type] (insert_edge may add attrs as a 4th
item); set_edge_attrs: [from, to, type, {attrs}]; set_node_attrs: [node, {attrs}];
remove_node_attrs: [node, [names]]; delete_node: name; any op may also be written as the full
op object of docs/FORMAT.md. ``$name`` anywhere in a value is replaced by its binding.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field
from typing import Any, Dict, Iterator, List, Optional, Tuple

from .exceptions import DsrError
from .graph import Graph

VAR = re.compile(r"\$[A-Za-z_][A-Za-z0-9_]*\Z")
WILDCARD = "_"
Bindings = Dict[str, Any]


class GrammarError(DsrError):
    """A rule is malformed; the message names the rule and the part."""


def is_var(value: Any) -> bool:
    return isinstance(value, str) and bool(VAR.match(value))


def substitute(value: Any, bindings: Bindings) -> Any:
    """``value`` with every ``$var`` replaced by its binding (recursively)."""
    if is_var(value):
        if value not in bindings:
            raise GrammarError(f"{value} is not bound")
        return bindings[value]
    if isinstance(value, list):
        return [substitute(v, bindings) for v in value]
    if isinstance(value, dict):
        return {k: substitute(v, bindings) for k, v in value.items()}
    return value


# ------------------------------------------------------------------ patterns
@dataclass
class Pattern:
    kind: str  # "edge", "no_edge", "node" or "no_node"
    src: Any = None
    dst: Any = None
    type: Any = None
    attrs: Dict[str, Any] = field(default_factory=dict)

    @classmethod
    def parse(cls, item: Any, where: str) -> "Pattern":
        if not isinstance(item, dict):
            raise GrammarError(f"{where}: a pattern is an object, got {item!r}")
        for kind in ("edge", "no_edge"):
            if kind in item:
                triple = item[kind]
                if not (isinstance(triple, list) and len(triple) == 3 and all(isinstance(t, str) for t in triple)):
                    raise GrammarError(f"{where}: {kind} is [from, to, type], got {triple!r}")
                extra = set(item) - {kind, "attrs"}
                if extra:
                    raise GrammarError(f"{where}: unknown keys {sorted(extra)}")
                return cls(kind, triple[0], triple[1], triple[2], dict(item.get("attrs") or {}))
        if "node" in item:
            extra = set(item) - {"node", "type", "attrs"}
            if extra:
                raise GrammarError(f"{where}: unknown keys {sorted(extra)}")
            return cls("node", item["node"], None, item.get("type"), dict(item.get("attrs") or {}))
        if "no_node" in item:
            if set(item) != {"no_node"} or not isinstance(item["no_node"], str):
                raise GrammarError(f"{where}: no_node is a node name or $variable")
            return cls("no_node", item["no_node"])
        raise GrammarError(f"{where}: a pattern has edge, no_edge, node or no_node, got {sorted(item)}")


def _bind(term: Any, actual: Any, bindings: Bindings) -> Optional[Bindings]:
    """Unify a pattern term with an actual value; the extended bindings or None."""
    if term == WILDCARD:
        return bindings
    if is_var(term):
        if term in bindings:
            return bindings if bindings[term] == actual else None
        return {**bindings, term: actual}
    return bindings if term == actual else None


def _attrs_match(pattern: Dict[str, Any], attrs: Dict[str, Any], bindings: Bindings) -> Optional[Bindings]:
    for name, term in pattern.items():
        if name not in attrs:
            return None
        bindings = _bind(term, attrs[name], bindings)
        if bindings is None:
            return None
    return bindings


def _resolve(term: Any, bindings: Bindings) -> Optional[str]:
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


def match(graph: Graph, patterns: List[Pattern], bindings: Optional[Bindings] = None) -> Iterator[Bindings]:
    """Every binding under which all patterns hold (positive patterns first, then negations)."""
    positive = [p for p in patterns if p.kind in ("edge", "node")]
    negative = [p for p in patterns if p.kind in ("no_edge", "no_node")]

    def holds(n: Pattern, b: Bindings) -> bool:
        as_positive = Pattern("edge" if n.kind == "no_edge" else "node", n.src, n.dst, n.type, n.attrs)
        return any(True for _ in _match_one(graph, as_positive, b))

    def walk(i: int, b: Bindings) -> Iterator[Bindings]:
        if i == len(positive):
            if not any(holds(n, b) for n in negative):
                yield b
            return
        for extended in _match_one(graph, positive[i], b):
            yield from walk(i + 1, extended)

    yield from walk(0, dict(bindings or {}))


def preconditions(patterns: List[Pattern], bindings: Bindings) -> List[Dict[str, Any]]:
    """The pattern as server-side checks, so the during write is a compare-and-set. Negations
    with a wildcard cannot be stated to the server and are checked locally only."""
    checks: List[Dict[str, Any]] = []
    for p in patterns:
        if p.kind == "no_node":
            if p.src != WILDCARD:
                checks.append({"check": "node_absent", "node": substitute(p.src, bindings)})
            continue
        if p.kind == "node":
            name = substitute(p.src, bindings)
            checks.append({"check": "node_exists", "node": name})
            checks += [{"check": "attr_equals", "node": name, "attr": a, "value": substitute(v, bindings)}
                       for a, v in p.attrs.items() if v != WILDCARD]
            continue
        if WILDCARD in (p.src, p.dst):
            continue
        edge = {"from": substitute(p.src, bindings), "to": substitute(p.dst, bindings), "type": p.type}
        checks.append({"check": "edge_exists" if p.kind == "edge" else "edge_absent", **edge})
        if p.kind == "edge":
            checks += [{"check": "attr_equals", **edge, "attr": a, "value": substitute(v, bindings)}
                       for a, v in p.attrs.items() if v != WILDCARD]
    return checks


# ------------------------------------------------------------------ ops
def expand_op(item: Any, where: str) -> Dict[str, Any]:
    """A shorthand op (see the module doc) as a full op object, variables left in place."""
    if not isinstance(item, dict) or len(item) != 1 and "op" not in item:
        raise GrammarError(f"{where}: an op is {{name: args}} or a full op object, got {item!r}")
    if "op" in item:
        return dict(item)
    (kind, args), = item.items()
    edge_keys = ("from", "to", "type")
    if kind in ("insert_edge", "delete_edge", "set_edge_attrs", "remove_edge_attrs") and isinstance(args, list):
        op = {"op": kind, **dict(zip(edge_keys, args[:3]))}
        if kind in ("insert_edge", "set_edge_attrs") and len(args) == 4:
            op["attrs"] = args[3]
        if kind == "remove_edge_attrs" and len(args) == 4:
            op["names"] = args[3]
        return op
    if kind in ("set_node_attrs", "remove_node_attrs") and isinstance(args, list) and len(args) == 2:
        return {"op": kind, "node": args[0], ("attrs" if kind == "set_node_attrs" else "names"): args[1]}
    if kind == "delete_node" and isinstance(args, str):
        return {"op": kind, "node": args}
    if isinstance(args, dict):
        return {"op": kind, **args}
    raise GrammarError(f"{where}: cannot read {kind} {args!r}")


# ------------------------------------------------------------------ rules
@dataclass
class Rule:
    name: str
    when: List[Pattern]
    during: List[Dict[str, Any]]
    after: Dict[str, List[Dict[str, Any]]] = field(default_factory=dict)
    process: Optional[str] = None
    once_per: Optional[List[str]] = None
    claim: List[Dict[str, Any]] = field(default_factory=list)
    priority: int = 0
    trigger: Optional[str] = None  # a percept event: the rule fires when the agent signals it

    @classmethod
    def parse(cls, doc: Any) -> "Rule":
        if not isinstance(doc, dict) or not isinstance(doc.get("name"), str):
            raise GrammarError(f"a rule is an object with a \"name\", got {doc!r}")
        name = doc["name"]
        unknown = set(doc) - {"name", "when", "during", "after", "process", "once_per", "claim", "priority", "doc",
                              "trigger", "given"}
        if unknown:
            raise GrammarError(f"rule {name}: unknown keys {sorted(unknown)}")
        when = [Pattern.parse(p, f"rule {name}: when[{i}]") for i, p in enumerate(doc.get("when") or [])]
        if not when:
            raise GrammarError(f"rule {name}: \"when\" needs at least one pattern")
        during = [expand_op(o, f"rule {name}: during[{i}]") for i, o in enumerate(doc.get("during") or [])]
        after_doc = doc.get("after") or {}
        if isinstance(after_doc, list):
            after_doc = {"done": after_doc}
        after = {outcome: [expand_op(o, f"rule {name}: after.{outcome}[{i}]") for i, o in enumerate(ops or [])]
                 for outcome, ops in after_doc.items()}
        if not during and not doc.get("process"):
            raise GrammarError(f"rule {name}: needs a \"during\" write or a \"process\"")
        if after and not doc.get("process"):
            raise GrammarError(f"rule {name}: \"after\" needs a \"process\" whose outcome selects it")
        once_per = doc.get("once_per")
        if once_per is not None and not (isinstance(once_per, list) and all(is_var(v) for v in once_per)):
            raise GrammarError(f"rule {name}: once_per is a list of $variables")
        trigger = doc.get("trigger")
        if trigger is not None and not isinstance(trigger, str):
            raise GrammarError(f"rule {name}: \"trigger\" is the name of a percept event")
        given = doc.get("given") or []
        if not (isinstance(given, list) and all(is_var(v) for v in given)) or (given and trigger is None):
            raise GrammarError(f"rule {name}: \"given\" lists the $variables a \"trigger\" event brings")
        rule = cls(name, when, during, after, doc.get("process"), once_per, list(doc.get("claim") or []),
                   int(doc.get("priority", 0)), trigger)
        rule._check_bound(set(given))
        return rule

    def _check_bound(self, given: set) -> None:
        bound = set(given)
        for p in self.when:
            if p.kind == "no_edge":
                continue
            for term in [p.src, p.dst, *p.attrs.values()]:
                if is_var(term):
                    bound.add(term)
        used = set(_vars(self.during)) | set(_vars(self.claim)) | set(self.once_per or [])
        used |= {v for p in self.when if p.kind in ("no_edge", "no_node") for v in _vars([p.src, p.dst])}
        missing = used - bound
        if missing:
            raise GrammarError(f"rule {self.name}: {', '.join(sorted(missing))} used but never bound in \"when\"")

    def key(self, bindings: Bindings) -> Tuple:
        names = self.once_per if self.once_per is not None else sorted(bindings)
        return tuple((n, repr(bindings.get(n))) for n in names)


def _vars(value: Any) -> Iterator[str]:
    if is_var(value):
        yield value
    elif isinstance(value, list):
        for v in value:
            yield from _vars(v)
    elif isinstance(value, dict):
        for v in value.values():
            yield from _vars(v)


def load_rules(docs: Any) -> List[Rule]:
    """Rules from a list of rule objects (as read from a YAML or JSON grammar file)."""
    if isinstance(docs, dict) and "rules" in docs:
        docs = docs["rules"]
    if not isinstance(docs, list):
        raise GrammarError("a grammar is a list of rules (or {\"rules\": [...]})")
    rules = [Rule.parse(d) for d in docs]
    names = [r.name for r in rules]
    dupes = {n for n in names if names.count(n) > 1}
    if dupes:
        raise GrammarError(f"rule names must be unique: {sorted(dupes)}")
    return rules


# ------------------------------------------------------------------ the engine (Algorithm 2)
@dataclass
class Firing:
    rule: Rule
    bindings: Bindings

    def during_tx(self) -> Dict[str, Any]:
        tx: Dict[str, Any] = {"preconditions": preconditions(self.rule.when, self.bindings),
                              "ops": substitute(self.rule.during, self.bindings)}
        if self.rule.claim:
            tx["claim"] = substitute(self.rule.claim, self.bindings)
        if self.rule.priority:
            tx["priority"] = self.rule.priority
        return tx

    def after_tx(self, outcome: str, extra: Optional[Bindings] = None) -> Optional[Dict[str, Any]]:
        """The after write for an outcome (None when the rule has none for it). It requires the
        during state to still hold: if something else undid it meanwhile, the after is refused."""
        bindings = {**self.bindings, **{(k if k.startswith("$") else "$" + k): v for k, v in (extra or {}).items()}}
        ops = self.rule.after.get(outcome)
        release = substitute(self.rule.claim, self.bindings) if self.rule.claim else []
        if ops is None:
            return {"ops": [], "release": release} if release else None
        held = [{"check": "edge_exists", "from": o["from"], "to": o["to"], "type": o["type"]}
                for o in substitute(self.rule.during, self.bindings) if o["op"] == "insert_edge"]
        tx: Dict[str, Any] = {"preconditions": held, "ops": substitute(ops, bindings)}
        if release:
            tx["release"] = release
        if self.rule.priority:
            tx["priority"] = self.rule.priority
        return tx


class GrammarEngine:
    """Which rules to fire now: search_for_changes of Algorithm 2, with the bookkeeping that
    keeps a rule from firing twice for the same situation."""

    def __init__(self, rules: List[Rule]):
        self.rules = rules
        self._busy: set = set()  # (rule name, key) sent or running
        self._last: Dict[str, Tuple] = {}  # rule name -> key of the last accepted firing (once_per)

    def search(self, graph: Graph) -> List[Firing]:
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

    def signal(self, graph: Graph, event: str, values: Dict[str, Any]) -> List[Firing]:
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
