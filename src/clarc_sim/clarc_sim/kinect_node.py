"""The Kinect stand-in: a frame every 1/rate_hz seconds saying whether a person is in front of
the robot and where their face is (mm, in the Kinect's frame, with a little jitter), following
the simulated patient.

ROS Parameters: rate_hz (50). Subscriptions: clarc/sim/patient/presence (latched).
Publishers: clarc/kinect/person.
"""

from __future__ import annotations

import json
import random

from clarc_agents import topics
from clarc_agents.agent_node import declare_float, get_float, main_for
from dsr_graph.qos import qos_latched, qos_stream
from rclpy.node import Node
from std_msgs.msg import String

from . import sim_topics


class KinectStandIn(Node):
    def __init__(self):
        super().__init__("kinect")
        declare_float(self, "rate_hz", 50.0, "frames per second")
        self.presence = {"present": False, "face": [0.0, 0.0, 0.0]}
        self._frames = self.create_publisher(String, topics.KINECT_PERSON, qos_stream())
        self.create_subscription(String, sim_topics.PATIENT_PRESENCE, self.on_presence, qos_latched())
        self._random = random.Random(7)

    def setup(self) -> None:
        self.create_timer(1.0 / get_float(self, "rate_hz"), self.on_frame)

    def on_presence(self, msg: String) -> None:
        try:
            doc = json.loads(msg.data)
            self.presence = {"present": bool(doc["present"]), "face": [float(v) for v in doc.get("face", [0, 0, 0])]}
        except (ValueError, KeyError, TypeError) as e:
            self.get_logger().warning(f"unreadable presence {msg.data!r}: {e}")

    def on_frame(self) -> None:
        frame = {"present": self.presence["present"]}
        if frame["present"]:
            frame["face"] = [v + self._random.uniform(-5, 5) for v in self.presence["face"]]
        self._frames.publish(String(data=json.dumps(frame)))


main = main_for(KinectStandIn)
