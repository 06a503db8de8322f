"""The Panel agent: shows each sentence (and its options as buttons, or the shapes, pictures or
text an item needs) on the touch screen, clears it when the person leaves, and turns a tap, the
shapes touched or a drawing into an answer. Rules: grammars/panel.yaml.

Publishers: clarc/panel/display (latched). Subscriptions: clarc/panel/tap. Plus the DSR topics.
"""

from __future__ import annotations

from typing import Any

from std_msgs.msg import String

from clarc_agents import topics
from clarc_agents.behaviours.panel import PanelBehaviour
from clarc_agents.nodes.grammar_agent import GrammarAgentNode
from dsr_graph.ros.dsr_node import main_for
from dsr_graph.ros.json_topics import publish_json, subscribe_json
from dsr_graph.ros.qos import qos_latched, qos_stream
from dsr_graph.rules.runner import Process


class PanelAgent(GrammarAgentNode):
    GRAMMAR = "panel"

    NAME = "panel"

    def __init__(self):
        super().__init__()
        self.behaviour = PanelBehaviour(
            self, self.get_logger(), server_gap=lambda: self.dsr.server_gap
        )

    def processes(self) -> dict[str, Process]:
        return self.behaviour.processes()

    def setup(self) -> None:
        self._display = self.create_publisher(String, topics.PANEL_DISPLAY, qos_latched())
        subscribe_json(self, topics.PANEL_TAP, self.on_tap, qos_stream())
        self.dsr.describe(can_do=["show", "take taps"], listens_to=[topics.PANEL_TAP])
        super().setup()
        self.dsr.add_listener(lambda d, r: self.behaviour.on_graph(self.runner, self.dsr.graph))

    def display(self, content: dict[str, Any]) -> None:  # the Screen protocol
        publish_json(self._display, content)

    def on_tap(self, tap: dict[str, Any]) -> None:
        self.behaviour.on_input(self.runner, self.dsr.graph, tap)


main = main_for(PanelAgent)
