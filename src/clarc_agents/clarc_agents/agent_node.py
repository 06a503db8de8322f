"""The shape every grammar-driven CLARC agent shares: a ROS node with a DSR replica and a
RuleRunner on its grammar file (``grammars/<name>.yaml``); subclasses give the processes."""

from __future__ import annotations

import abc
from importlib import resources
from typing import Dict, List, Optional

from dsr_graph.agent import DsrAgent
from dsr_graph.node_main import run_node, setup_and_spin
from dsr_graph.rule_agent import Process, RuleRunner, load_grammar_file
from rcl_interfaces.msg import ParameterDescriptor
from rclpy.node import Node


def declare_float(node: Node, name: str, default: float, description: str = "", read_only: bool = False) -> None:
    """A number parameter that also accepts an integer on the command line (``-p time_scale:=1``)."""
    node.declare_parameter(name, float(default), ParameterDescriptor(
        description=description, read_only=read_only, dynamic_typing=True))


def get_float(node: Node, name: str) -> float:
    return float(node.get_parameter(name).value)


def grammar_path(name: str) -> str:
    return str(resources.files("clarc_agents").joinpath(f"grammars/{name}.yaml"))


class GrammarAgentNode(Node, abc.ABC):
    """ROS Parameters: time_scale (float, scales every time of the flow), setup_timeout (float).
    Subscriptions/Publishers: those of DsrAgent, plus the subclass's own devices."""

    GRAMMAR = ""

    def __init__(self, node_name: str):
        super().__init__(node_name)
        declare_float(self, "time_scale", 1.0, "multiplies every time of the flow (0.1: ten times faster than a real session)")
        declare_float(self, "setup_timeout", 20.0, "seconds to wait for the DSR server", read_only=True)
        self.dsr = DsrAgent()
        self.runner: Optional[RuleRunner] = None

    @property
    def scale(self) -> float:
        return get_float(self, "time_scale")

    @abc.abstractmethod
    def processes(self) -> Dict[str, Process]:
        """The processes the grammar's rules name, by name."""

    def setup(self) -> None:
        self.dsr.setup(self, timeout_sec=get_float(self, "setup_timeout"))
        self.runner = RuleRunner(self.dsr, load_grammar_file(grammar_path(self.GRAMMAR)), self.processes(),
                                 self.get_logger())
        self.runner.setup()
        self.get_logger().info(f"{self.GRAMMAR} agent up: {len(self.runner.engine.rules)} rules")


def run(node_class, args: Optional[List[str]] = None) -> int:
    """The main() of every CLARC node: init, setup, spin, clean shutdown."""
    return run_node(node_class, setup_and_spin, args)


def main_for(node_class):
    def main(args: Optional[List[str]] = None) -> int:
        return run(node_class, args)
    return main


