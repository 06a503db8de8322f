"""Running declared grammar rules for an agent: the paper's Algorithm 2.

    on every change of the agent's graph:
        search_for_changes  -> the rules whose "before" holds (GrammarEngine.search)
        publish "during"    -> sent with "before" as preconditions; if another agent was first,
                               the server refuses it and nothing runs
        process { action }  -> the agent's process, called once the during write is accepted
        publish "after"     -> chosen by the process's outcome

A process is ``process(ctx)``: it returns an outcome ("done", or any name the rule's ``after``
knows) or a dict of extra bindings (outcome "done"); or it returns None and calls
``ctx.finish(outcome, **bindings)`` later (speech that takes time). If the rule's claims are
preempted by a higher priority, ``ctx.preempted`` becomes true and ``ctx.on_preempted`` runs.
A claim the server ended because this agent was out of its reach (``unreachable``: a network
cut) is taken again while the action still runs; if another agent took it meanwhile, the action
is preempted.

Pure: the runner talks to the DSR through an ``AgentLink`` (``dsr_graph.ros.agent.DsrAgent`` over
ROS, ``dsr_graph.protocol.local_bus`` in one process).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any, Protocol

from dsr_graph.model.claims import target_key
from dsr_graph.model.graph import Graph
from dsr_graph.protocol.server_core import Result
from dsr_graph.rules.engine import Firing, GrammarEngine
from dsr_graph.rules.syntax import Rule

Listener = Callable[
    [list[dict[str, Any]], bool], None
]  # (applied deltas, resynced from a snapshot)


class AgentLink(Protocol):
    """What the runner needs of an agent's connection to the DSR."""

    name: str

    @property
    def graph(self) -> Graph: ...

    @property
    def synced(self) -> bool: ...

    def send(self, doc: dict[str, Any], on_done: Callable[[Any], None] | None = None) -> str: ...

    def add_listener(self, listener: Listener) -> None: ...


Process = Callable[["ActionContext"], Any]


class ActionContext:
    def __init__(self, runner: RuleRunner, firing: Firing):
        self._runner = runner
        self.firing = firing
        self.done = False
        self.preempted = False
        self.on_preempted: Callable[[], None] | None = None

    @property
    def rule(self) -> Rule:
        return self.firing.rule

    def __getitem__(self, name: str) -> Any:
        """A binding by name, with or without its ``$``."""
        return self.firing.bindings[name if name.startswith("$") else "$" + name]

    def finish(self, outcome: str = "done", **extra: Any) -> None:
        if not self.done:
            self.done = True
            self._runner._finish(self, outcome, extra)


class RuleRunner:
    def __init__(self, agent: AgentLink, rules: list[Rule], processes: dict[str, Process], logger):
        missing = {r.process for r in rules if r.process and r.process not in processes}
        if missing:
            raise ValueError(f"rules name processes this agent does not have: {sorted(missing)}")
        self.agent = agent
        self.engine = GrammarEngine(rules)
        self.processes = processes
        self.log = logger
        self.running: list[ActionContext] = []
        self.fired = 0
        self.lost = 0  # during writes refused because another agent was first

    def setup(self) -> None:
        self.agent.add_listener(self._on_change)

    def _on_change(self, deltas: list[dict[str, Any]], resynced: bool) -> None:
        for delta in deltas:
            self._note_preemptions(delta)
        self.step()

    def step(self) -> None:
        for firing in self.engine.search(self.agent.graph):
            self.engine.started(firing)
            self._take(firing)

    def _take(self, firing: Firing) -> None:
        """Write the firing's "during" (a compare-and-set); a rule that writes nothing and claims
        nothing runs its process at once, on the pattern its agent's graph matched."""
        if not firing.rule.during and not firing.rule.claim:
            self._on_during(firing, Result("", True))
            return
        self.agent.send(firing.during_tx(), lambda result, f=firing: self._on_during(f, result))

    def signal(self, event: str, **values: Any) -> int:
        """A percept happened (a tap, a face): fire the rules it triggers. Returns how
        many rules fired (their writes still go through the server's compare-and-set)."""
        if not self.agent.synced:
            return 0
        firings = self.engine.signal(self.agent.graph, event, values)
        for firing in firings:
            self._take(firing)
        return len(firings)

    def _on_during(self, firing: Firing, result) -> None:
        if firing.rule.trigger is not None and not result.accepted:
            self.log.debug(f"rule {firing.rule.name}: percept not taken ({result.error})")
            return
        self.engine.handled(firing)
        if not result.accepted:
            self.lost += 1
            self.log.debug(f"rule {firing.rule.name}: not taken ({result.error})")
            self.engine.finished(firing)
            self.step()
            return
        self.fired += 1
        self.log.info(
            f"rule {firing.rule.name}: taken" + (f" at seq {result.seq}" if result.seq else "")
        )
        if not firing.rule.process:
            self.engine.finished(firing)
            self.step()
            return
        ctx = ActionContext(self, firing)
        self.running.append(ctx)
        try:
            returned = self.processes[firing.rule.process](ctx)
        except Exception as e:  # a failing process must not stop the agent
            self.log.error(f"rule {firing.rule.name}: process {firing.rule.process} failed: {e!r}")
            ctx.finish("failed")
            return
        if isinstance(returned, str):
            ctx.finish(returned)
        elif isinstance(returned, dict):
            ctx.finish("done", **returned)

    def _finish(self, ctx: ActionContext, outcome: str, extra: dict[str, Any]) -> None:
        firing = ctx.firing
        if ctx in self.running:
            self.running.remove(ctx)
        tx = firing.after_tx(outcome, extra)

        def done(result) -> None:
            if result is not None and not result.accepted:
                self.log.info(f"rule {firing.rule.name}: after ({outcome}) refused: {result.error}")
            self.engine.finished(firing)
            self.step()

        if tx is None:
            done(None)
        else:
            self.agent.send(tx, done)

    def _note_preemptions(self, delta: dict[str, Any]) -> None:
        for item in delta.get("claims", {}).get("released", []):
            reason = item.get("reason")
            if item.get("agent") != self.agent.name or reason not in ("preempted", "unreachable"):
                continue
            key = target_key(item["target"])
            for ctx in self.running:
                claimed = {target_key(t) for t in ctx.firing.during_tx().get("claim", [])}
                if key not in claimed or ctx.preempted or ctx.done:
                    continue
                if reason == "preempted":
                    self._preempted(ctx, f"preempted by {item.get('by')}")
                else:
                    self._claim_again(ctx, item["target"])

    def _claim_again(self, ctx: ActionContext, target: dict[str, str]) -> None:
        self.log.warning(
            f"rule {ctx.rule.name}: claim on {target} ended while we were out of the server's "
            "reach: taking it again"
        )

        def done(result) -> None:
            if not result.accepted and not ctx.done and not ctx.preempted:
                self._preempted(
                    ctx, f"taken by another while we were out of reach ({result.error})"
                )

        self.agent.send({"claim": [target]}, done)

    def _preempted(self, ctx: ActionContext, why: str) -> None:
        ctx.preempted = True
        self.log.warning(f"rule {ctx.rule.name}: claim {why}")
        if ctx.on_preempted is not None:
            ctx.on_preempted()
