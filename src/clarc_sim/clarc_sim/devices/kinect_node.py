"""The Kinect stand-in: a frame every 1/rate_hz seconds saying whether a person is in front of
the robot and where their face is (mm, in the Kinect's frame, with a little jitter), following
the simulated patient.

ROS Parameters: rate_hz (50). Subscriptions: clarc/sim/patient/presence (latched).
Publishers: clarc/kinect/person.
"""

from __future__ import annotations

import random
from typing import Any

from std_msgs.msg import String

from clarc_agents import topics
from clarc_sim import sim_topics
from dsr_graph.ros.dsr_node import DsrNode, main_for
from dsr_graph.ros.json_topics import publish_json, subscribe_json
from dsr_graph.ros.parameters import declare, float_param
from dsr_graph.ros.qos import qos_latched, qos_sensor


class KinectStandIn(DsrNode):
    NAME = "kinect"

    @classmethod
    def declare_node_parameters(cls, node) -> None:
        declare(node, "rate_hz", 50.0, "frames per second", read_only=True, minimum=0.1)

    def __init__(self):
        super().__init__()
        self.presence: dict[str, Any] = {"present": False, "face": [0.0, 0.0, 0.0]}
        self._random = random.Random(7)

    def setup(self) -> None:
        self._frames = self.create_publisher(String, topics.KINECT_PERSON, qos_sensor())
        subscribe_json(self, sim_topics.PATIENT_PRESENCE, self.on_presence, qos_latched())
        self.create_timer(1.0 / float_param(self, "rate_hz"), self.on_frame)

    def on_presence(self, doc: dict[str, Any]) -> None:
        self.presence = {
            "present": bool(doc["present"]),
            "face": [float(v) for v in doc.get("face", [0, 0, 0])],
        }

    def on_frame(self) -> None:
        frame: dict[str, Any] = {"present": self.presence["present"]}
        if frame["present"]:
            frame["face"] = [v + self._random.uniform(-5, 5) for v in self.presence["face"]]
        publish_json(self._frames, frame)


main = main_for(KinectStandIn)
