"""The simulated patient: sits in front of CLARC, listens to what it says and answers by voice
or on the touch screen, stays silent, mumbles or walks away, as its scenario file says.

ROS Parameters: scenario (path, required), time_scale (1.0), reaction (1.0 s before answering),
face (mm in the Kinect's frame, default [900, 0, -400]). Subscriptions: clarc/speaker/events.
Publishers: clarc/sim/patient/voice, clarc/sim/patient/touch, clarc/sim/patient/presence
(latched).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from std_msgs.msg import String

from clarc_agents import topics
from clarc_sim import sim_topics
from clarc_sim.patient.scenario import load
from clarc_sim.patient.script import Action, PatientScript
from dsr_graph.ros.dsr_node import DsrNode, main_for
from dsr_graph.ros.json_topics import publish_json, subscribe_json
from dsr_graph.ros.parameters import declare, float_param, param
from dsr_graph.ros.qos import qos_latched, qos_stream
from dsr_graph.ros.timers import OneShot


class SimulatedPatient(DsrNode):
    NAME = "patient"

    @classmethod
    def declare_node_parameters(cls, node) -> None:
        declare(node, "scenario", "", "scenario YAML file", read_only=True, required=True)
        declare(node, "time_scale", 1.0, "multiplies every time", read_only=True, minimum=0.0)
        declare(
            node, "reaction", 1.0, "seconds before the patient answers", read_only=True, minimum=0.0
        )
        declare(node, "face", [900.0, 0.0, -400.0], "where the face is, in the Kinect's frame (mm)")

    def __init__(self):
        super().__init__()
        self.script: PatientScript | None = None

    def setup(self) -> None:
        scenario = load(param(self, "scenario"))  # a ScenarioError ends the node, naming the line
        self.script = PatientScript(scenario, reaction=float_param(self, "reaction"))
        self._voice = self.create_publisher(String, sim_topics.PATIENT_VOICE, qos_stream())
        self._touch = self.create_publisher(String, sim_topics.PATIENT_TOUCH, qos_stream())
        self._presence = self.create_publisher(String, sim_topics.PATIENT_PRESENCE, qos_latched())
        subscribe_json(self, topics.SPEAKER, self.on_speaker, qos_stream())
        self._set_present(True)
        self.get_logger().info(f"{scenario.patient} sits in front of the robot ({scenario.source})")

    def _later(self, seconds: float, action: Callable[[], None]) -> None:
        OneShot(self, seconds * float_param(self, "time_scale"), action)

    def _set_present(self, present: bool) -> None:
        self.script.present = present
        publish_json(self._presence, {"present": present, "face": list(param(self, "face"))})

    def on_speaker(self, event: dict[str, Any]) -> None:
        for action in self.script.heard(str(event["text"]), str(event["event"])):
            self._later(action.delay, lambda a=action: self._do(a))

    def _do(self, action: Action) -> None:
        if action.kind == "leave":
            self.get_logger().info(f"walks away for {action.seconds} s")
            self._set_present(False)
            self._later(
                action.seconds, lambda: (self.get_logger().info("is back"), self._set_present(True))
            )
        elif not self.script.present:
            return
        elif action.kind == "say":
            self.get_logger().info(f"says {action.text!r}")
            publish_json(self._voice, {"text": action.text})
        elif action.kind == "tap":
            self.get_logger().info(f"touches the option worth {action.points}")
            publish_json(self._touch, {"points": action.points})


main = main_for(SimulatedPatient)
