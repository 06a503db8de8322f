"""The simulated patient: sits in front of CLARC, listens to what it says and answers by voice
or on the touch screen (a tap, shapes touched, a drawing), closes the eyes when asked to, stays
silent, mumbles or walks away, as its scenario file says; it knows the date and where it is
(``place``, as PELEA's), so it answers orientation as its scenario says. In a
Get Up & Go scenario it sits on the trial's chair and, when it hears "go", does the trial of its
``motion:``, or its ``recording:`` from ``offset:`` (the Kinect stand-in draws the body or plays
the recording, from clarc/sim/patient/trial), walking out of view once if the scenario says
``leave``.

ROS Parameters: scenario (path, required), time_scale (1.0), reaction (1.0 s before answering),
face (mm in the Kinect's frame, default [900, 0, -400]), place (PELEA's default).
Subscriptions: clarc/speaker/events.
Publishers: clarc/sim/patient/voice (with the scenario's voice), clarc/sim/patient/touch,
clarc/sim/patient/presence (latched), clarc/sim/room (latched: the scenario's room noise and
SNR), clarc/sim/patient/trial (latched, Get Up & Go).
"""

from __future__ import annotations

import time
from collections.abc import Callable
from datetime import date
from typing import Any

from std_msgs.msg import String

from clarc_agents import definitions, topics
from clarc_agents.gug import sentences as gug
from clarc_agents.questionnaire.orientation import DEFAULT_PLACE, values
from clarc_sim import sim_topics
from clarc_sim.patient.scenario import MOTION_KEYS, load
from clarc_sim.patient.script import Action, PatientScript
from dsr_graph.ros.dsr_node import DsrNode, main_for
from dsr_graph.ros.json_topics import publish_json, subscribe_json
from dsr_graph.ros.parameters import declare, declare_time_scale, float_param, param
from dsr_graph.ros.qos import qos_latched, qos_stream
from dsr_graph.ros.timers import OneShot

LEAVE_AWAY = 3.0  # seconds (of the patient's time) out of view when leaving a trial


class SimulatedPatient(DsrNode):
    NAME = "patient"

    @classmethod
    def declare_node_parameters(cls, node) -> None:
        declare(node, "scenario", "", "scenario YAML file", read_only=True, required=True)
        declare_time_scale(node)
        declare(
            node, "reaction", 1.0, "seconds before the patient answers", read_only=True, minimum=0.0
        )
        declare(node, "face", [900.0, 0.0, -400.0], "where the face is, in the Kinect's frame (mm)")
        declare(node, "place", list(DEFAULT_PLACE), "where the patient is (as PELEA's place)")

    def __init__(self):
        super().__init__()
        self.script: PatientScript | None = None  # a questionnaire's; none in a timed test
        self._present = True

    def setup(self) -> None:
        scenario = load(param(self, "scenario"))  # a ScenarioError ends the node, naming the line
        if scenario.test in definitions.tests():
            known = values(date.today(), tuple(param(self, "place")), scenario.language)
            definition = definitions.load(scenario.test, scenario.language).filled(known)
            self.script = PatientScript(scenario, definition, float_param(self, "reaction"))
        self._voice = self.create_publisher(String, sim_topics.PATIENT_VOICE, qos_stream())
        self._touch = self.create_publisher(String, sim_topics.PATIENT_TOUCH, qos_stream())
        self._presence = self.create_publisher(String, sim_topics.PATIENT_PRESENCE, qos_latched())
        self._room = self.create_publisher(String, sim_topics.ROOM, qos_latched())
        room = {"noise": scenario.noise, "snr_db": scenario.snr_db, "voice": list(scenario.voice)}
        publish_json(self._room, room)
        self.scenario = scenario
        self._left = False
        self._eyes_closed = False
        if scenario.test == "get_up_and_go":
            self._trial = self.create_publisher(String, sim_topics.PATIENT_TRIAL, qos_latched())
            self._publish_trial(None)
        subscribe_json(self, topics.SPEAKER, self.on_speaker, qos_stream())
        self._set_present(True)
        self.get_logger().info(f"{scenario.patient} sits in front of the robot ({scenario.source})")

    def _later(self, seconds: float, action: Callable[[], None]) -> None:
        OneShot(self, seconds * float_param(self, "time_scale"), action)

    def _set_present(self, present: bool) -> None:
        if self.script is not None:
            self.script.present = present
        self._present = present
        presence = {"present": present, "face": list(param(self, "face"))}
        publish_json(self._presence, presence | {"eyes_closed": self._eyes_closed})

    def _set_eyes(self, closed: bool) -> None:
        self._eyes_closed = closed
        self._set_present(self._present)

    def _publish_trial(self, go: float | None) -> None:
        s = self.scenario
        trial = {"go": go, "noise_mm": s.noise_mm, "drop_rate": s.drop_rate}
        trial["tracking_losses"] = s.tracking_losses
        trial["rises"] = s.rises
        if s.recording is not None:
            trial |= {"recording": s.recording, "offset": s.offset}
        else:
            trial["motion"] = {k: getattr(s.motion, k) for k in MOTION_KEYS}
        publish_json(self._trial, trial)

    def _on_gug_speaker(self, event: dict[str, Any]) -> None:
        if event["event"] != "end" or event["text"] != gug.GO or not self._present:
            return
        s = self.scenario
        what = f"the recording {s.recording}" if s.recording else f"a {s.motion.total:.1f} s trial"
        if s.rises:
            self.get_logger().info(f"hears go: gets up ({what})")
        else:
            self.get_logger().info("hears go: cannot get up")
        # from when the speaker ended "go" (its stamp), as the robot times it, however late we
        # heard of it
        self._publish_trial(float(event.get("stamp", time.time())))
        if self.scenario.leave is not None and not self._left:
            self._left = True
            self._later(self.scenario.leave, self._leave_trial)

    def _leave_trial(self) -> None:
        self.get_logger().info(f"walks out of view for {LEAVE_AWAY} s, then sits down again")
        self._set_present(False)
        self._publish_trial(None)  # back on the chair when seen again

        def back() -> None:
            self.get_logger().info("is back on the chair")
            self._set_present(True)

        self._later(LEAVE_AWAY, back)

    def on_speaker(self, event: dict[str, Any]) -> None:
        if self.scenario.test == "get_up_and_go":
            self._on_gug_speaker(event)
            return
        for action in self.script.heard(str(event["text"]), str(event["event"])):
            self._later(action.delay, lambda a=action: self._do(a))

    def _do(self, action: Action) -> None:
        if action.kind == "leave":
            self.get_logger().info(f"walks away for {action.seconds} s")
            self._set_present(False)
            self._later(
                action.seconds, lambda: (self.get_logger().info("is back"), self._set_present(True))
            )
        elif not self._present:
            return
        elif action.kind == "close_eyes":
            self.get_logger().info(f"closes the eyes for {action.seconds} s")
            self._set_eyes(True)
            self._later(action.seconds, lambda: self._set_eyes(False))
        elif action.kind == "touch":
            self.get_logger().info(f"touches the {action.text} on the screen")
            publish_json(self._touch, {"target": action.text})
        elif action.kind == "draw":
            self.get_logger().info(f"draws on the screen ({len(action.text)} characters of path)")
            publish_json(self._touch, {"drawing": action.text})
        elif action.kind == "say":
            self.get_logger().info(f"says {action.text!r}")
            publish_json(self._voice, {"text": action.text, "voice": list(self.scenario.voice)})
        elif action.kind == "tap":
            self.get_logger().info(f"touches the option worth {action.points}")
            publish_json(self._touch, {"points": action.points})


main = main_for(SimulatedPatient)
