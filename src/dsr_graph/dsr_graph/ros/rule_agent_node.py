"""``dsr_rule_agent``: a ROS node that runs a grammar file with generic processes (``wait``,
``instant``): useful to prototype an agent, and the harness of the runtime's own tests.

ROS Parameters:
    grammar_file (str): YAML or JSON list of rules.
    process_time (float): seconds the generic ``wait`` process takes (default 0.2).
    setup_timeout (float): seconds to wait for the DSR server (default 10).
Subscriptions, publishers, clients: those of DsrAgent.
"""

from __future__ import annotations

from dsr_graph.ros.agent import DsrAgent
from dsr_graph.ros.dsr_node import DsrNode, main_for
from dsr_graph.ros.parameters import declare, declare_setup_timeout, float_param, param
from dsr_graph.ros.timers import OneShot
from dsr_graph.rules.runner import ActionContext, RuleRunner
from dsr_graph.rules.syntax import load_grammar_file


class RuleAgentNode(DsrNode):
    NAME = "dsr_rule_agent"

    @classmethod
    def declare_node_parameters(cls, node) -> None:
        declare(node, "grammar_file", "", "YAML/JSON list of rules", read_only=True, required=True)
        declare(node, "process_time", 0.2, "seconds the wait process takes", minimum=0.0)
        declare_setup_timeout(node, 10.0)

    def __init__(self) -> None:
        super().__init__()
        self.agent = DsrAgent()
        self.runner: RuleRunner | None = None

    def setup(self) -> None:
        rules = load_grammar_file(param(self, "grammar_file"))
        self.agent.setup(self, timeout_sec=float_param(self, "setup_timeout"))
        processes = {"wait": self.wait, "instant": lambda ctx: "done"}
        self.runner = RuleRunner(self.agent, rules, processes, self.get_logger())
        self.runner.setup()
        self.get_logger().info(f"running {len(rules)} rules as {self.agent.name}")

    def wait(self, ctx: ActionContext) -> None:
        """Finish after process_time seconds (a stand-in for any action that takes time)."""
        OneShot(
            self,
            float_param(self, "process_time"),
            lambda: ctx.finish("preempted" if ctx.preempted else "done"),
        )


main = main_for(RuleAgentNode)
