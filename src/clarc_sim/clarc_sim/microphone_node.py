"""The microphone + speech recognition stand-in: what the patient says reaches the robot as
recognised text after a short latency (scaled). Mumbling comes out as mumbling: recognising it
is the Speech agent's job.

ROS Parameters: time_scale (1.0), latency (0.4 s). Subscriptions: clarc/sim/patient/voice.
Publishers: clarc/asr.
"""

from __future__ import annotations

import json

from clarc_agents import topics
from clarc_agents.agent_node import declare_float, get_float, main_for
from dsr_graph.qos import qos_stream
from rclpy.node import Node
from std_msgs.msg import String

from . import sim_topics


class MicrophoneStandIn(Node):
    def __init__(self):
        super().__init__("microphone")
        declare_float(self, "time_scale", 1.0, "multiplies every time")
        declare_float(self, "latency", 0.4, "seconds speech recognition takes")
        self._asr = self.create_publisher(String, topics.ASR, qos_stream())
        self.create_subscription(String, sim_topics.PATIENT_VOICE, self.on_voice, qos_stream())

    def setup(self) -> None:
        pass

    def on_voice(self, msg: String) -> None:
        try:
            text = str(json.loads(msg.data)["text"])
        except (ValueError, KeyError, TypeError) as e:
            self.get_logger().warning(f"unreadable voice {msg.data!r}: {e}")
            return
        delay = get_float(self, "latency") * get_float(self, "time_scale")
        timer = None

        def recognised() -> None:
            timer.cancel()
            self.destroy_timer(timer)
            self._asr.publish(String(data=json.dumps({"text": text})))

        timer = self.create_timer(max(delay, 0.001), recognised)


main = main_for(MicrophoneStandIn)
