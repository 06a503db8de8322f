"""The shape every grammar-driven CLARC agent shares: a ROS node with a DSR replica and a
RuleRunner on its grammar file (``grammars/<name>.yaml``); subclasses give the processes and
attach their devices in ``setup()``."""

from __future__ import annotations

import abc

from clarc_agents.grammar_files import load_grammar
from dsr_graph.ros.agent import DsrAgent
from dsr_graph.ros.dsr_node import DsrNode
from dsr_graph.ros.parameters import declare, float_param
from dsr_graph.rules.runner import Process, RuleRunner


class GrammarAgentNode(DsrNode, abc.ABC):
    """ROS Parameters: time_scale (float, scales every time of the flow), setup_timeout (float).
    Subscriptions/Publishers: those of DsrAgent, plus the subclass's own devices."""

    GRAMMAR = ""

    def __init__(self, node_name: str):
        super().__init__(node_name)
        declare(
            self,
            "time_scale",
            1.0,
            "multiplies every time of the flow (0.1: ten times faster than a real session)",
            read_only=True,
            minimum=0.0,
        )
        declare(
            self,
            "setup_timeout",
            20.0,
            "seconds to wait for the DSR server",
            read_only=True,
            minimum=0.0,
        )
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
        self.get_logger().info(f"{self.GRAMMAR} agent up: {len(self.runner.engine.rules)} rules")
