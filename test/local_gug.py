"""The CLARC robot running a Get Up & Go test in one process, on virtual time (no ROS): PELEA's
GugExecutive, Speech, Panel and Person on a LocalBus, the gait analyser reading only the DSR,
and a patient whose body the Kinect sees (gait_motion, skeleton_frames): on the end of "go" it
does its trial, 30 frames a second, each written by Person as one transaction."""

from __future__ import annotations

import math
import random

from clarc_agents.gug import sentences
from clarc_agents.gug.gait_analyser import GaitAnalyser
from clarc_agents.gug.posture import PostureTracker, pelvis_in_room
from clarc_agents.gug.skeleton import parse_skeleton, skeleton_tx
from clarc_agents.pelea.gug_executive import GugExecutive
from clarc_agents.pelea.hle import Times
from clarc_sim.devices.skeleton_frames import KinectModel, TrialPlace, dropped, skeleton
from clarc_sim.patient.gait_motion import Motion

from local_clarc import FACE, Robot, log

PLACE = TrialPlace(4500.0, 0.0, -1200.0, math.pi)  # the CLARC room's gug_chair
LEAVE_AWAY = 3.0
HZ = 30.0


class GugRobot(Robot):
    def __init__(
        self,
        motion: Motion,
        noise_mm: float = 0.0,
        drop_rate: float = 0.0,
        leave: float | None = None,
        rises: bool = True,
        seen_for: float | None = None,
        hz: float = HZ,
        lag_per_second: float = 0.0,
        analyser: bool = True,
    ):
        """``seen_for``: seconds after go the Kinect sees the patient (default: the motion and
        3 s more); ``lag_per_second``: a busy machine, each frame reaching the DSR this many
        seconds later per second since go (its stamp still its capture time); ``analyser``:
        whether a gait analyser runs."""
        super().__init__()
        self.motion, self.noise_mm, self.drop_rate = motion, noise_mm, drop_rate
        self.leave, self.rises, self.left_trial = leave, rises, False
        self.seen_for = motion.total + 3.0 if seen_for is None else seen_for
        self.hz, self.lag_per_second = hz, lag_per_second
        self.gug = GugExecutive(self.port, Times(), log)
        self.pelea_link.add_listener(lambda d, r: self.gug.on_graph(self.pelea_link.graph))
        self.analyser_link = self.bus.agent("/gait_analyser")
        self.analyser = GaitAnalyser()
        if analyser:
            self.analyser_link.add_listener(lambda d, r: self._analyse(None if r else d))
        self.rng = random.Random(11)
        self.trial = 0
        self.present = True
        self._texts: dict[int, str] = {}
        self.posture = PostureTracker()
        self.postures: list[str] = []  # as the person node says, in order
        self.bus.agent("/posture_watch").add_listener(lambda d, r: self._note_posture())

    def run_gug(self, patient: str = "Carlos", limit: float = 3600.0):
        self.gug.start(self.pelea_link.graph, patient)
        self.bus.run(until=self.over, limit=limit)
        return self.port.stored[-1] if self.port.stored else None

    def over(self) -> bool:
        return self.bus.core.graph.node("test").attrs.get("status") == "finished" and not (
            self.gug.running
        )

    def restart_pelea(self) -> None:
        super().restart_pelea()
        self.gug = GugExecutive(self.port, Times(), log)
        self.pelea_link.add_listener(lambda d, r: self.gug.on_graph(self.pelea_link.graph))
        self.gug.on_graph(self.pelea_link.graph)

    # ------------------------------------------------------------------ the analyser
    def restart_analyser(self) -> None:
        """The gait analyser's process dies and a new one starts, knowing nothing."""
        self.analyser_link.close()
        self.analyser_link = self.bus.agent("/gait_analyser")
        self.analyser = GaitAnalyser()
        self.analyser_link.add_listener(lambda d, r: self._analyse(None if r else d))

    def _analyse(self, deltas=None) -> None:
        tx = self.analyser.on_graph(self.analyser_link.graph, deltas)
        if tx is not None:
            self.analyser_link.send(tx)

    # ------------------------------------------------------------------ the patient's body
    def say(self, sid: int, text: str) -> None:
        self._texts[sid] = text
        super().say(sid, text)

    def _spoken(self, sid: int, event: str) -> None:
        super()._spoken(sid, event)
        if event == "end" and self._texts.get(sid) == sentences.GO and self.present:
            self._start_trial()

    def _start_trial(self) -> None:
        self.trial += 1
        trial, go = self.trial, self.bus.now
        sensor = KinectModel(self.rng, self.noise_mm)  # a Kinect's noise, new for each trial
        if self.leave is not None and not self.left_trial:
            self.left_trial = True
            self.bus.after(self.leave, self._walk_away)

        def deliver(joints, stamp: float) -> None:
            self.person_link.send(skeleton_tx(self.person_link.graph, joints, stamp))
            # what Person does with the frame's geometry: the posture percept
            pelvis = pelvis_in_room(self.person_link.graph, joints)
            posture = self.posture.update(stamp, pelvis)
            if posture is not None:
                self.person.signal("posture", posture=posture)

        def frame() -> None:
            if trial != self.trial or not self.present:
                return
            t = self.bus.now - go
            if not self.rises:
                t = min(t, -0.1)  # stays seated
            if not dropped(self.rng, self.drop_rate):
                raw, _ = sensor.see(skeleton(self.motion, t, PLACE), t)
                joints, stamp = parse_skeleton(raw), self.port.epoch()
                lag = self.lag_per_second * (self.bus.now - go)
                if lag > 0.0:  # later frames are later still: never out of order
                    self.bus.after(lag, lambda: deliver(joints, stamp))
                else:
                    deliver(joints, stamp)
            if self.bus.now - go < self.seen_for:
                self.bus.after(1.0 / self.hz, frame)

        frame()

    def _note_posture(self) -> None:
        person = self.bus.core.graph.find("person")
        posture = None if person is None else person.attrs.get("posture")
        if posture and (not self.postures or self.postures[-1] != posture):
            self.postures.append(posture)

    def _walk_away(self) -> None:
        self.present = False
        self.trial += 1  # the frames of the trial in progress stop
        self.person.signal("lost")

        def back() -> None:
            self.present = True
            self.person.signal("seen", pose=FACE)

        self.bus.after(LEAVE_AWAY, back)
