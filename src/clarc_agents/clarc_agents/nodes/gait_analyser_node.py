"""The gait analyser as a ROS node: a new compoNet that reads only the DSR. While PELEA's gait
node says a Get Up & Go trial is being timed, it follows the person's joints there (geometric
children of the person, updated per Kinect frame by Person), writes the phase in progress as it
changes and, once the patient is seated again, the timed trial (``gug/gait_analyser.py``). It
neither reads the scenario nor the Kinect's topic.

ROS Parameters: time_scale (1.0: the session's pace, to give times in the patient's time),
setup_timeout (20). Subscriptions/Publishers: the DSR topics (DsrAgent).
"""

from __future__ import annotations

from clarc_agents.gug.gait_analyser import GaitAnalyser
from dsr_graph.ros.agent import DsrAgent
from dsr_graph.ros.dsr_node import DsrNode, main_for
from dsr_graph.ros.parameters import declare_setup_timeout, declare_time_scale, float_param


class GaitAnalyserNode(DsrNode):
    NAME = "gait_analyser"

    @classmethod
    def declare_node_parameters(cls, node) -> None:
        declare_time_scale(
            node, "the session's pace: frame times are divided by it to give the patient's time"
        )
        declare_setup_timeout(node, 20.0)

    def __init__(self):
        super().__init__()
        self.dsr = DsrAgent()
        self.analyser = GaitAnalyser(scale=float_param(self, "time_scale"))
        self._in_flight = False
        self._next: dict | None = None

    def setup(self) -> None:
        self.dsr.describe(can_do=["time a Get Up & Go"])
        self.dsr.setup(self, timeout_sec=float_param(self, "setup_timeout"))
        # every frame of the deltas counts; after a resynchronisation, the graph's latest
        self.dsr.add_listener(lambda deltas, resynced: self.on_graph(None if resynced else deltas))
        self.get_logger().info("gait analyser up: waiting for a Get Up & Go trial")

    def on_graph(self, deltas=None) -> None:
        tx = self.analyser.on_graph(self.dsr.graph, deltas)
        if tx is not None:
            self._next = tx  # a later write says all an earlier one would (phase, then result)
        self._send_next()

    def _send_next(self) -> None:
        if self._next is None or self._in_flight:
            return
        tx, self._next = self._next, None
        attrs = tx["ops"][0]["attrs"]
        self._in_flight = True

        def done(result) -> None:
            self._in_flight = False
            if not result.accepted:  # the trial ended meanwhile (PELEA voided it)
                self.get_logger().warning(f"gait not written: {result.error}")
            elif attrs.get("status") == "void":
                self.get_logger().warning(f"trial void: {attrs.get('reason', '')}")
            elif "tug_seconds" in attrs:
                self.get_logger().info(
                    f"trial timed: {attrs['tug_seconds']} s ({attrs['band']}), phases "
                    f"{attrs['phase_seconds']}"
                )
            self._send_next()

        self.dsr.send(tx, done)


main = main_for(GaitAnalyserNode)
