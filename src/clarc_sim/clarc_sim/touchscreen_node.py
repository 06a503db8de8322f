"""The touch screen stand-in: shows what the Panel agent sends, and turns the patient's touch
on a shown option into a tap for the Panel. A touch where no option is shown does nothing.

Subscriptions: clarc/panel/display (latched), clarc/sim/patient/touch. Publishers:
clarc/panel/tap.
"""

from __future__ import annotations

import json

from clarc_agents import topics
from clarc_agents.agent_node import main_for
from dsr_graph.qos import qos_latched, qos_stream
from rclpy.node import Node
from std_msgs.msg import String

from . import sim_topics


class TouchscreenStandIn(Node):
    def __init__(self):
        super().__init__("touchscreen")
        self.shown: dict = {}
        self._tap = self.create_publisher(String, topics.PANEL_TAP, qos_stream())
        self.create_subscription(String, topics.PANEL_DISPLAY, self.on_display, qos_latched())
        self.create_subscription(String, sim_topics.PATIENT_TOUCH, self.on_touch, qos_stream())

    def setup(self) -> None:
        pass

    def on_display(self, msg: String) -> None:
        try:
            self.shown = json.loads(msg.data)
        except ValueError:
            self.shown = {}
        self.get_logger().info("screen: " + ("(blank)" if self.shown.get("clear") else str(self.shown.get("text"))))

    def on_touch(self, msg: String) -> None:
        try:
            points = int(json.loads(msg.data)["points"])
        except (ValueError, KeyError, TypeError) as e:
            self.get_logger().warning(f"unreadable touch {msg.data!r}: {e}")
            return
        shown_points = [int(p) for p in self.shown.get("option_points", [])]
        if points not in shown_points:
            self.get_logger().info(f"touch on {points} points, but that option is not on the screen")
            return
        text = self.shown["options"][shown_points.index(points)]
        self._tap.publish(String(data=json.dumps({"points": points, "text": text})))


main = main_for(TouchscreenStandIn)
