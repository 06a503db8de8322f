"""Running declared grammar rules in a ROS node: the paper's Algorithm 2.

    on every change of the replica:
        search_for_changes  -> the rules whose "before" holds (GrammarEngine.search)
        publish "during"    -> sent with "before" as preconditions; if another agent was first,
                               the server refuses it and nothing runs
        process { action }  -> the agent's process, called once the during write is accepted
        publish "after"     -> chosen by the process's outcome

A process is ``process(ctx)``: it returns an outcome ("done", or any name the rule's ``after``
knows) or a dict of extra bindings (outcome "done"); or it returns None and calls
``ctx.finish(outcome, **bindings)`` later (speech that takes time). If the rule's claims are
preempted by a higher priority, ``ctx.preempted`` becomes true and ``ctx.on_preempted`` runs.

``dsr_rule_agent`` (console script) runs a grammar file with generic processes (see PROCESSES):
useful to prototype an agent, and the harness of the runtime's own tests.

ROS Parameters (dsr_rule_agent):
    grammar_file (str): YAML or JSON list of rules.
    process_time (float): seconds the generic ``wait`` process takes (default 0.2).
"""

from __future__ import annotations

import sys
from typing import Any, Callable, Dict, List, Optional

from .agent import DsrAgent, Result
from .claims import target_key
from .grammar import Firing, GrammarEngine, Rule

Process = Callable[["ActionContext"], Any]


class ActionContext:
    def __init__(self, runner: "RuleRunner", firing: Firing):
        self._runner = runner
        self.firing = firing
        self.done = False
        self.preempted = False
        self.on_preempted: Optional[Callable[[], None]] = None

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
    def __init__(self, agent: DsrAgent, rules: List[Rule], processes: Dict[str, Process], logger):
        missing = {r.process for r in rules if r.process and r.process not in processes}
        if missing:
            raise ValueError(f"rules name processes this agent does not have: {sorted(missing)}")
        self.agent = agent
        self.engine = GrammarEngine(rules)
        self.processes = processes
        self.log = logger
        self.running: List[ActionContext] = []
        self.fired = 0
        self.lost = 0  # during writes refused because another agent was first

    def setup(self) -> None:
        self.agent.add_listener(self._on_change)

    def _on_change(self, deltas: List[Dict[str, Any]], resynced: bool) -> None:
        for delta in deltas:
            self._note_preemptions(delta)
        self.step()

    def step(self) -> None:
        for firing in self.engine.search(self.agent.graph):
            self.engine.started(firing)
            self.agent.send(firing.during_tx(), lambda result, f=firing: self._on_during(f, result))

    def signal(self, event: str, **values: Any) -> int:
        """A percept happened (a tap, a face): fire the rules it triggers. Returns how
        many rules fired (their writes still go through the server's compare-and-set)."""
        if not self.agent.replica.synced:
            return 0
        firings = self.engine.signal(self.agent.graph, event, values)
        for firing in firings:
            self.agent.send(firing.during_tx(), lambda result, f=firing: self._on_during(f, result))
        return len(firings)

    def _on_during(self, firing: Firing, result: Result) -> None:
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
        self.log.info(f"rule {firing.rule.name}: during accepted at seq {result.seq}")
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

    def _finish(self, ctx: ActionContext, outcome: str, extra: Dict[str, Any]) -> None:
        firing = ctx.firing
        if ctx in self.running:
            self.running.remove(ctx)
        tx = firing.after_tx(outcome, extra)

        def done(result: Optional[Result]) -> None:
            if result is not None and not result.accepted:
                self.log.info(f"rule {firing.rule.name}: after ({outcome}) refused: {result.error}")
            self.engine.finished(firing)
            self.step()

        if tx is None:
            done(None)
        else:
            self.agent.send(tx, done)

    def _note_preemptions(self, delta: Dict[str, Any]) -> None:
        for item in delta.get("claims", {}).get("released", []):
            if item.get("agent") != self.agent.name or item.get("reason") != "preempted":
                continue
            key = target_key(item["target"])
            for ctx in self.running:
                claimed = {target_key(t) for t in ctx.firing.during_tx().get("claim", [])}
                if key in claimed and not ctx.preempted:
                    ctx.preempted = True
                    self.log.warning(f"rule {ctx.rule.name}: claim preempted by {item.get('by')}")
                    if ctx.on_preempted is not None:
                        ctx.on_preempted()


# ------------------------------------------------------------------ the generic agent node
def _generic_processes(node) -> Dict[str, Process]:
    def wait(ctx: ActionContext) -> None:
        """Finish after process_time seconds (a stand-in for any action that takes time)."""
        timer = None

        def fire() -> None:
            timer.cancel()
            ctx.finish("preempted" if ctx.preempted else "done")

        timer = node.create_timer(node.get_parameter("process_time").value, fire)

    def instant(ctx: ActionContext) -> str:
        return "done"

    return {"wait": wait, "instant": instant}


PROCESSES = ("wait", "instant")


def load_grammar_file(path: str) -> List[Rule]:
    import yaml

    from .grammar import load_rules

    with open(path, encoding="utf-8") as f:
        return load_rules(yaml.safe_load(f))


def main(args: Optional[List[str]] = None) -> int:
    import rclpy
    from rcl_interfaces.msg import ParameterDescriptor

    from .node_main import run_node

    def make():
        node = rclpy.create_node("dsr_rule_agent")
        node.declare_parameter("grammar_file", "", ParameterDescriptor(description="YAML/JSON list of rules", read_only=True))
        node.declare_parameter("process_time", 0.2, ParameterDescriptor(description="seconds the wait process takes"))
        node.declare_parameter("setup_timeout", 10.0, ParameterDescriptor(description="seconds to wait for the server", read_only=True))
        return node

    def body(node) -> None:
        rules = load_grammar_file(node.get_parameter("grammar_file").value)
        agent = DsrAgent()
        agent.setup(node, timeout_sec=node.get_parameter("setup_timeout").value)
        RuleRunner(agent, rules, _generic_processes(node), node.get_logger()).setup()
        node.get_logger().info(f"running {len(rules)} rules as {agent.name}")
        rclpy.spin(node)

    return run_node(make, body, args)


if __name__ == "__main__":
    sys.exit(main())
