"""The microphone + speech recognition stand-in: what the patient says reaches the robot as
recognised text after a short latency (scaled). Mumbling comes out as mumbling: recognising it
is the Speech agent's job.

ROS Parameters: time_scale (1.0), latency (0.4 s). Subscriptions: clarc/sim/patient/voice.
Publishers: clarc/asr.
"""

from __future__ import annotations

from typing import Any

from std_msgs.msg import String

from clarc_agents import topics
from clarc_sim import sim_topics
from dsr_graph.ros.dsr_node import DsrNode, main_for
from dsr_graph.ros.json_topics import publish_json, subscribe_json
from dsr_graph.ros.parameters import declare, declare_time_scale, float_param
from dsr_graph.ros.qos import qos_stream
from dsr_graph.ros.timers import OneShot


class MicrophoneStandIn(DsrNode):
    NAME = "microphone"

    @classmethod
    def declare_node_parameters(cls, node) -> None:
        declare_time_scale(node)
        declare(node, "latency", 0.4, "seconds speech recognition takes", minimum=0.0)

    def __init__(self):
        super().__init__()

    def setup(self) -> None:
        self._asr = self.create_publisher(String, topics.ASR, qos_stream())
        subscribe_json(self, sim_topics.PATIENT_VOICE, self.on_voice, qos_stream())

    def on_voice(self, voice: dict[str, Any]) -> None:
        text = str(voice["text"])
        delay = float_param(self, "latency") * float_param(self, "time_scale")
        OneShot(self, delay, lambda: publish_json(self._asr, {"text": text}))


main = main_for(MicrophoneStandIn)
