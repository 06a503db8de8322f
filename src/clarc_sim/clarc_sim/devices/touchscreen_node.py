"""The touch screen stand-in: shows what the Panel agent sends, and turns the patient's touch
on a shown option into a tap for the Panel. A touch where no option is shown does nothing.

Subscriptions: clarc/panel/display (latched), clarc/sim/patient/touch. Publishers:
clarc/panel/tap.
"""

from __future__ import annotations

from typing import Any

from std_msgs.msg import String

from clarc_agents import topics
from clarc_sim import sim_topics
from dsr_graph.ros.dsr_node import DsrNode, main_for
from dsr_graph.ros.json_topics import publish_json, subscribe_json
from dsr_graph.ros.qos import qos_latched, qos_stream


class TouchscreenStandIn(DsrNode):
    NAME = "touchscreen"

    def __init__(self):
        super().__init__()
        self.shown: dict[str, Any] = {}

    def setup(self) -> None:
        self._tap = self.create_publisher(String, topics.PANEL_TAP, qos_stream())
        subscribe_json(self, topics.PANEL_DISPLAY, self.on_display, qos_latched())
        subscribe_json(self, sim_topics.PATIENT_TOUCH, self.on_touch, qos_stream())

    def on_display(self, shown: dict[str, Any]) -> None:
        self.shown = shown
        self.get_logger().info(
            "screen: " + ("(blank)" if shown.get("clear") else str(shown.get("text")))
        )

    def on_touch(self, touch: dict[str, Any]) -> None:
        points = int(touch["points"])
        shown_points = [int(p) for p in self.shown.get("option_points", [])]
        if points not in shown_points:
            self.get_logger().info(
                f"touch on {points} points, but that option is not on the screen"
            )
            return
        text = self.shown["options"][shown_points.index(points)]
        publish_json(self._tap, {"points": points, "text": text})


main = main_for(TouchscreenStandIn)
