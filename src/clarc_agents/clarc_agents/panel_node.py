"""The Panel agent: shows each sentence (and its options as buttons) on the touch screen,
clears it when the person leaves, and turns a tap into an answer. Rules: grammars/panel.yaml.

Publishers: clarc/panel/display (latched). Subscriptions: clarc/panel/tap. Plus the DSR topics.
"""

from __future__ import annotations

import json
from typing import Dict

from dsr_graph.qos import qos_latched, qos_stream
from dsr_graph.rule_agent import ActionContext, Process
from std_msgs.msg import String

from . import topics
from .agent_node import GrammarAgentNode, main_for


class PanelAgent(GrammarAgentNode):
    GRAMMAR = "panel"

    def __init__(self):
        super().__init__("panel")
        self._display = self.create_publisher(String, topics.PANEL_DISPLAY, qos_latched())
        self.create_subscription(String, topics.PANEL_TAP, self.on_tap, qos_stream())

    def processes(self) -> Dict[str, Process]:
        return {"show": self.show, "clear": self.clear}

    def show(self, ctx: ActionContext) -> str:
        self._display.publish(String(data=json.dumps({
            "sid": ctx["sid"], "text": ctx["text"], "options": ctx["options"], "option_points": ctx["points"]})))
        return "done"

    def clear(self, ctx: ActionContext) -> str:
        self._display.publish(String(data=json.dumps({"clear": True})))
        return "done"

    def on_tap(self, msg: String) -> None:
        try:
            points = int(json.loads(msg.data)["points"])
        except (ValueError, KeyError, TypeError) as e:
            self.get_logger().warning(f"unreadable tap {msg.data!r}: {e}")
            return
        if not self.runner.signal("tap", points=points):
            self.get_logger().info(f"tap on {points} points while no answer is awaited: ignored")


main = main_for(PanelAgent)
