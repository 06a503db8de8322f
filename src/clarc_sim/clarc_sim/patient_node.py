"""The simulated patient: sits in front of CLARC, listens to what it says and answers by voice
or on the touch screen, stays silent, mumbles or walks away, as its scenario file says.

ROS Parameters: scenario (path, required), time_scale (1.0), reaction (1.0 s before answering),
face (mm in the Kinect's frame, default [900, 0, -400]). Subscriptions: clarc/speaker/events.
Publishers: clarc/sim/patient/voice, clarc/sim/patient/touch, clarc/sim/patient/presence
(latched).
"""

from __future__ import annotations

import json
from typing import Callable

from clarc_agents import topics
from clarc_agents.agent_node import declare_float, get_float, main_for
from dsr_graph.exceptions import DsrError
from dsr_graph.qos import qos_latched, qos_stream
from rcl_interfaces.msg import ParameterDescriptor
from rclpy.node import Node
from std_msgs.msg import String

from . import sim_topics
from .patient_script import Action, PatientScript
from .scenario import ScenarioError, load


class ScenarioUnusable(DsrError):
    pass


class SimulatedPatient(Node):
    def __init__(self):
        super().__init__("patient")
        self.declare_parameter("scenario", "", ParameterDescriptor(description="scenario YAML file", read_only=True))
        declare_float(self, "time_scale", 1.0, "multiplies every time")
        declare_float(self, "reaction", 1.0, "seconds before the patient answers")
        self.declare_parameter("face", [900.0, 0.0, -400.0])
        self._voice = self.create_publisher(String, sim_topics.PATIENT_VOICE, qos_stream())
        self._touch = self.create_publisher(String, sim_topics.PATIENT_TOUCH, qos_stream())
        self._presence = self.create_publisher(String, sim_topics.PATIENT_PRESENCE, qos_latched())
        self.script = None

    def setup(self) -> None:
        try:
            scenario = load(self.get_parameter("scenario").value)
        except ScenarioError as e:
            raise ScenarioUnusable(str(e)) from e
        self.script = PatientScript(scenario, reaction=get_float(self, "reaction"))
        self.create_subscription(String, topics.SPEAKER, self.on_speaker, qos_stream())
        self._set_present(True)
        self.get_logger().info(f"{scenario.patient} sits in front of the robot ({scenario.source})")

    def _scaled(self, seconds: float) -> float:
        return max(seconds * get_float(self, "time_scale"), 0.001)

    def _later(self, seconds: float, action: Callable[[], None]) -> None:
        timer = None

        def fire() -> None:
            timer.cancel()
            self.destroy_timer(timer)
            action()

        timer = self.create_timer(self._scaled(seconds), fire)

    def _set_present(self, present: bool) -> None:
        self.script.present = present
        face = list(self.get_parameter("face").value)
        self._presence.publish(String(data=json.dumps({"present": present, "face": face})))

    def on_speaker(self, msg: String) -> None:
        try:
            event = json.loads(msg.data)
            actions = self.script.heard(str(event["text"]), str(event["event"]))
        except (ValueError, KeyError, TypeError) as e:
            self.get_logger().warning(f"unreadable speaker event {msg.data!r}: {e}")
            return
        for action in actions:
            self._later(action.delay, lambda a=action: self._do(a))

    def _do(self, action: Action) -> None:
        if action.kind == "leave":
            self.get_logger().info(f"walks away for {action.seconds} s")
            self._set_present(False)
            self._later(action.seconds, lambda: (self.get_logger().info("is back"), self._set_present(True)))
        elif not self.script.present:
            return
        elif action.kind == "say":
            self.get_logger().info(f"says {action.text!r}")
            self._voice.publish(String(data=json.dumps({"text": action.text})))
        elif action.kind == "tap":
            self.get_logger().info(f"touches the option worth {action.points}")
            self._touch.publish(String(data=json.dumps({"points": action.points})))


main = main_for(SimulatedPatient)
