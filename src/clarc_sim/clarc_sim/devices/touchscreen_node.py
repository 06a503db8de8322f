"""The touch screen stand-in: shows what the Panel agent sends, and turns the patient's touch
on a shown option into a tap for the Panel, a touch on a shown shape into a touch on it, and a
finished drawing (while the screen takes one) into the drawing. A touch where nothing it takes
is shown does nothing.

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
        if "target" in touch or "drawing" in touch:
            self._on_shape_or_drawing(touch)
            return
        points = int(touch["points"])
        shown_points = [int(p) for p in self.shown.get("option_points", [])]
        if points not in shown_points:
            self.get_logger().info(
                f"touch on {points} points, but that option is not on the screen"
            )
            return
        text = self.shown["options"][shown_points.index(points)]
        publish_json(self._tap, {"points": points, "text": text})

    def _on_shape_or_drawing(self, touch: dict[str, Any]) -> None:
        takes = self.shown.get("input", "")
        if "target" in touch:
            shapes = [str(s).lower() for s in self.shown.get("shows", [])]
            target = str(touch["target"]).lower()
            if takes != "targets" or target not in shapes:
                self.get_logger().info(f"touch on the {target}, but no such shape is on the screen")
                return
            publish_json(self._tap, {"target": target})
        elif takes != "drawing":
            self.get_logger().info("a drawing, but the screen is not taking one")
        else:
            publish_json(self._tap, {"drawing": str(touch["drawing"])})


main = main_for(TouchscreenStandIn)
