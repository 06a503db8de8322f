"""Grammar rules declared as data (paper, Fig. 3 and Algorithm 2): a *before* pattern, the
*during* write, the process to run, and the *after* write. Pure logic: ``matching`` finds
where a pattern holds, ``engine`` decides which rules fire, ``runner`` runs them (Algorithm 2).

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
    claim: [{from: robot, to: speaking}]   # held while the process runs (optional); its
                                           # priority is the agent's, from the server's policy
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
from collections.abc import Iterator
from dataclasses import dataclass, field
from typing import Any

from dsr_graph.exceptions import GrammarError

VAR = re.compile(r"\$[A-Za-z_][A-Za-z0-9_]*\Z")
WILDCARD = "_"
Bindings = dict[str, Any]


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
    attrs: dict[str, Any] = field(default_factory=dict)

    @classmethod
    def parse(cls, item: Any, where: str) -> Pattern:
        if not isinstance(item, dict):
            raise GrammarError(f"{where}: a pattern is an object, got {item!r}")
        for kind in ("edge", "no_edge"):
            if kind in item:
                triple = item[kind]
                if not (
                    isinstance(triple, list)
                    and len(triple) == 3
                    and all(isinstance(t, str) for t in triple)
                ):
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
        raise GrammarError(
            f"{where}: a pattern has edge, no_edge, node or no_node, got {sorted(item)}"
        )


# ------------------------------------------------------------------ ops
def expand_op(item: Any, where: str) -> dict[str, Any]:
    """A shorthand op (see the module doc) as a full op object, variables left in place."""
    if not isinstance(item, dict) or len(item) != 1 and "op" not in item:
        raise GrammarError(f"{where}: an op is {{name: args}} or a full op object, got {item!r}")
    if "op" in item:
        return dict(item)
    ((kind, args),) = item.items()
    edge_keys = ("from", "to", "type")
    if kind in ("insert_edge", "delete_edge", "set_edge_attrs", "remove_edge_attrs") and isinstance(
        args, list
    ):
        op = {"op": kind, **dict(zip(edge_keys, args[:3], strict=False))}
        if kind in ("insert_edge", "set_edge_attrs") and len(args) == 4:
            op["attrs"] = args[3]
        if kind == "remove_edge_attrs" and len(args) == 4:
            op["names"] = args[3]
        return op
    if (
        kind in ("set_node_attrs", "remove_node_attrs")
        and isinstance(args, list)
        and len(args) == 2
    ):
        return {
            "op": kind,
            "node": args[0],
            ("attrs" if kind == "set_node_attrs" else "names"): args[1],
        }
    if kind == "delete_node" and isinstance(args, str):
        return {"op": kind, "node": args}
    if isinstance(args, dict):
        return {"op": kind, **args}
    raise GrammarError(f"{where}: cannot read {kind} {args!r}")


# ------------------------------------------------------------------ rules
@dataclass
class Rule:
    name: str
    when: list[Pattern]
    during: list[dict[str, Any]]
    after: dict[str, list[dict[str, Any]]] = field(default_factory=dict)
    process: str | None = None
    once_per: list[str] | None = None
    claim: list[dict[str, Any]] = field(default_factory=list)
    trigger: str | None = None  # a percept event: the rule fires when the agent signals it

    @classmethod
    def parse(cls, doc: Any) -> Rule:
        if not isinstance(doc, dict) or not isinstance(doc.get("name"), str):
            raise GrammarError(f'a rule is an object with a "name", got {doc!r}')
        name = doc["name"]
        unknown = set(doc) - {
            "name",
            "when",
            "during",
            "after",
            "process",
            "once_per",
            "claim",
            "priority",  # of earlier grammars: accepted, ignored (the server's policy decides)
            "doc",
            "trigger",
            "given",
        }
        if unknown:
            raise GrammarError(f"rule {name}: unknown keys {sorted(unknown)}")
        when = [
            Pattern.parse(p, f"rule {name}: when[{i}]") for i, p in enumerate(doc.get("when") or [])
        ]
        if not when:
            raise GrammarError(f'rule {name}: "when" needs at least one pattern')
        during = [
            expand_op(o, f"rule {name}: during[{i}]") for i, o in enumerate(doc.get("during") or [])
        ]
        after_doc = doc.get("after") or {}
        if isinstance(after_doc, list):
            after_doc = {"done": after_doc}
        after = {
            outcome: [
                expand_op(o, f"rule {name}: after.{outcome}[{i}]") for i, o in enumerate(ops or [])
            ]
            for outcome, ops in after_doc.items()
        }
        if not during and not doc.get("process"):
            raise GrammarError(f'rule {name}: needs a "during" write or a "process"')
        if after and not doc.get("process"):
            raise GrammarError(f'rule {name}: "after" needs a "process" whose outcome selects it')
        once_per = doc.get("once_per")
        if once_per is not None and not (
            isinstance(once_per, list) and all(is_var(v) for v in once_per)
        ):
            raise GrammarError(f"rule {name}: once_per is a list of $variables")
        trigger = doc.get("trigger")
        if trigger is not None and not isinstance(trigger, str):
            raise GrammarError(f'rule {name}: "trigger" is the name of a percept event')
        given = doc.get("given") or []
        if not (isinstance(given, list) and all(is_var(v) for v in given)) or (
            given and trigger is None
        ):
            raise GrammarError(
                f'rule {name}: "given" lists the $variables a "trigger" event brings'
            )
        rule = cls(
            name,
            when,
            during,
            after,
            doc.get("process"),
            once_per,
            list(doc.get("claim") or []),
            trigger,
        )
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
        used |= {
            v for p in self.when if p.kind in ("no_edge", "no_node") for v in _vars([p.src, p.dst])
        }
        missing = used - bound
        if missing:
            raise GrammarError(
                f'rule {self.name}: {", ".join(sorted(missing))} used but never bound in "when"'
            )

    def key(self, bindings: Bindings) -> tuple:
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


def load_rules(docs: Any) -> list[Rule]:
    """Rules from a list of rule objects (as read from a YAML or JSON grammar file)."""
    if isinstance(docs, dict) and "rules" in docs:
        docs = docs["rules"]
    if not isinstance(docs, list):
        raise GrammarError('a grammar is a list of rules (or {"rules": [...]})')
    rules = [Rule.parse(d) for d in docs]
    names = [r.name for r in rules]
    dupes = {n for n in names if names.count(n) > 1}
    if dupes:
        raise GrammarError(f"rule names must be unique: {sorted(dupes)}")
    return rules


def load_grammar_file(path: str) -> list[Rule]:
    """The rules of a YAML (or JSON, which YAML reads too) grammar file."""
    import yaml

    with open(path, encoding="utf-8") as f:  # libyaml's safe loader where PyYAML has it
        return load_rules(yaml.load(f, Loader=getattr(yaml, "CSafeLoader", yaml.SafeLoader)))
