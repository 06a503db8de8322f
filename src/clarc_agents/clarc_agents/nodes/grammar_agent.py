"""The shape every grammar-driven CLARC agent shares: a ROS node with a DSR replica and a
RuleRunner on its grammar file (``grammars/<name>.yaml``); subclasses give the processes and
attach their devices in ``setup()``. With its first graph, an agent signals ``recover``: its
grammar's recovery rules take over an action a killed run of it left half done."""

from __future__ import annotations

import abc

from clarc_agents.grammar_files import load_grammar
from dsr_graph.ros.agent import DsrAgent
from dsr_graph.ros.dsr_node import DsrNode
from dsr_graph.ros.parameters import declare_setup_timeout, declare_time_scale, float_param
from dsr_graph.rules.runner import Process, RuleRunner


class GrammarAgentNode(DsrNode, abc.ABC):
    """ROS Parameters: time_scale (float, scales every time of the flow), setup_timeout (float).
    Subscriptions/Publishers: those of DsrAgent, plus the subclass's own devices."""

    GRAMMAR = ""

    @classmethod
    def declare_node_parameters(cls, node) -> None:
        declare_time_scale(
            node, "multiplies every time of the flow (0.1: ten times faster than a real session)"
        )
        declare_setup_timeout(node, 20.0)

    def __init__(self):
        super().__init__()
        self.dsr = DsrAgent()
        self.runner: RuleRunner | None = None

    @property
    def scale(self) -> float:
        return float_param(self, "time_scale")

    @abc.abstractmethod
    def processes(self) -> dict[str, Process]:
        """The processes the grammar's rules name, by name."""

    def setup(self) -> None:
        self.dsr.setup(self, timeout_sec=float_param(self, "setup_timeout"))
        self.runner = RuleRunner(
            self.dsr, load_grammar(self.GRAMMAR), self.processes(), self.get_logger()
        )
        self.runner.setup()
        self._recovered = False
        self.dsr.add_listener(self._recover_once)
        self.get_logger().info(f"{self.GRAMMAR} agent up: {len(self.runner.engine.rules)} rules")

    def _recover_once(self, deltas, resynced) -> None:
        """Crash-only: with the first graph this process sees, fire the grammar's ``recover``
        rules, which take over what a previous run of this agent left in the middle."""
        if not self._recovered and self.dsr.synced:
            self._recovered = True
            taken = self.runner.signal("recover")
            if taken:
                self.get_logger().warning(f"recovering {taken} action(s) a previous run left")
