"""The gait analyser's logic (pure): it sees only the DSR. While PELEA's ``gait`` node says a
trial is being timed (``status: timing``, ``go_at``, ``trial``), every new skeleton frame of the
person becomes a sample in the Get Up & Go chair's frame (the kinematic chain ``gug_chair`` ->
``kinect``, then the frame's own poses of the person and its joints): read from the deltas, so
that every frame Person wrote counts, several in one delta when Person fell behind, and several
deltas applied at once when this agent did (``skeleton.frames_in``; without deltas, after a
resynchronisation, the graph's latest frame); the phase in progress is written as it changes,
and once the patient has walked and is seated again the whole trial is timed
(``phases.time_trial``) and written back: ``tug_seconds``, ``phase_seconds`` (in ``PHASES``
order), ``band``, ``fall_risk``, ``status: timed``. Times are the frames' (``frame_time``,
epoch seconds) turned into the patient's time with ``scale`` (the session's pace), so a result
is the same at any pace.
"""

from __future__ import annotations

import math
from collections.abc import Iterator
from typing import Any

from clarc_agents.gug.phases import (
    MAX_GAP,
    PHASES,
    NotATrial,
    Sample,
    band,
    fall_risk,
    sample,
    time_trial,
)
from clarc_agents.gug.skeleton import frames_in, joint_node
from dsr_graph.exceptions import DsrError
from dsr_graph.model.graph import Graph

CHAIR = "gug_chair"
WATCHED = ("pelvis", "hip_left", "hip_right", "shoulder_left", "shoulder_right")
SEATED_FOR = 1.0  # s of the patient's time seated again before the trial is timed
ORDER = ("waiting", *PHASES, "done")
FAR = 1.5  # m from the chair: the patient walked


class GaitAnalyser:
    def __init__(self, scale: float = 1.0):
        self.scale = scale or 1.0
        self.trial: Any = None
        self.go = 0.0
        self.samples: list[Sample] = []
        self.phase = ""
        self._last_frame = None
        self._sensor_gap: float | None = None  # of the frame just taken, as Person wrote it
        self._reset()

    def _reset(self) -> None:
        """What is followed of the trial as frames come, so each frame costs the same."""
        self.samples = []
        self.walked = False  # the hips have been FAR from the chair
        self.last_up = 0.0  # when the hips were last above the seated height
        self.tried = float("-inf")  # when timing the whole trial was last tried

    def on_graph(
        self, graph: Graph, deltas: list[dict[str, Any]] | None = None
    ) -> dict[str, Any] | None:
        """The transaction to send for this state of the graph, if any; ``deltas``: the ones
        just applied, whose every frame is a sample (None: only the graph's latest frame)."""
        gait = graph.find("gait")
        if gait is None or gait.attrs.get("status") != "timing":
            self.trial = None
            return None
        if gait.attrs.get("trial") != self.trial:
            self.trial, self.go = gait.attrs.get("trial"), float(gait.attrs.get("go_at", 0.0))
            self.phase, self._last_frame = "waiting", None
            self._reset()
        news = self._frames(graph, deltas) if deltas is not None else [self._take_frame(graph)]
        tx = None
        for new in news:  # each frame taken, then judged, before the next is taken
            if self.phase == "done":
                break
            if new is not None:
                tx = self._on_sample(new) or tx  # a later write says what an earlier would
        return tx

    def _on_sample(self, new: Sample) -> dict[str, Any] | None:
        before = self.samples[-2].t if len(self.samples) > 1 else 0.0  # "go"
        # frames the sensor gave but the DSR could not take in time (a busy machine) are no
        # hole: only a gap of the sensor's own (Person's sensor_gap) voids the trial
        sensor_gap = None if self._sensor_gap is None else self._sensor_gap / self.scale
        hole = new.t - before > MAX_GAP and (sensor_gap is None or sensor_gap > MAX_GAP)
        if hole:  # Person or the Kinect was down, or we joined late
            self.phase = "done"
            reason = (
                f"no frames for {new.t - before:.1f} s from {before:.1f} s after go: "
                "the trial cannot be timed"
            )
            return self._tx({"status": "void", "phase": "done", "reason": reason})
        timed = self._time_if_seated()
        if timed is not None:
            return self._result_tx(timed)
        phase = self._phase_now()
        # the phase in progress only moves on (noise must not make it flicker back)
        if ORDER.index(phase) > ORDER.index(self.phase):
            self.phase = phase
            return self._tx({"phase": phase})
        return None

    # ------------------------------------------------------------------ samples
    def _frames(self, graph: Graph, deltas: list[dict[str, Any]]) -> Iterator[Sample | None]:
        """A sample per frame the deltas wrote, in their order (taken one at a time)."""
        frames = [frame for delta in deltas for frame in frames_in(delta)]
        if not frames or graph.find(CHAIR) is None:
            return
        try:
            chair_kinect = graph.transform(CHAIR, "kinect")
        except DsrError:
            return
        for stamp, person, joints in frames:
            if stamp == self._last_frame:
                continue
            self._last_frame = stamp
            self._sensor_gap = joints.pop("sensor_gap", None)
            seen = {
                joint: (chair_kinect @ person @ joints[joint])[:3, 3]
                for joint in WATCHED
                if joint in joints
            }
            yield self._add(stamp, seen)

    def _take_frame(self, graph: Graph) -> Sample | None:
        person = graph.find("person")
        if person is None or graph.find(CHAIR) is None:
            return None
        frame = person.attrs.get("frame_time")
        if frame is None or frame == self._last_frame:
            return None
        self._last_frame = frame
        # (the graph holds the latest frame only: a gap the sensor reported for frames this
        # agent did not see cannot be told from one it did not, so it is not taken)
        self._sensor_gap = None
        joints = {}
        for joint in WATCHED:
            if graph.find(joint_node(joint)) is None:
                continue
            try:
                joints[joint] = graph.transform(CHAIR, joint_node(joint))[:3, 3]
            except DsrError:  # not in one tree (yet): no sample from this frame
                return None
        return self._add(frame, joints)

    def _add(self, frame: float, joints: dict[str, Any]) -> Sample | None:
        """The sample of a frame (its time, the watched joints in the chair's frame), kept
        when it comes after "go"."""
        s = sample((float(frame) - self.go) / self.scale, joints)
        if s is not None and s.t >= 0.0:
            self.samples.append(s)
            self.walked = self.walked or s.distance > FAR
            if len(self.samples) <= 15 or s.height > self._seated_height() + 0.05:
                self.last_up = s.t
            return s
        return None

    # ------------------------------------------------------------------ the trial
    def _seated_height(self) -> float:
        """The lowest of the first frames after go: the patient still sits."""
        return min(s.height for s in self.samples[:15])

    def _phase_now(self) -> str:
        last, seated = self.samples[-1], self._seated_height()
        turned = abs(last.heading - self.samples[0].heading)
        turned = min(turned, 2 * math.pi - turned)
        if not self.walked:
            return "rise" if last.height > seated + 0.1 else "waiting"
        if last.distance > FAR and turned < 0.8:
            return "walk_out"
        if last.distance > FAR and turned < 2.4:
            return "turn"
        if last.distance > 0.5:
            return "walk_back"
        return "sit"

    def _time_if_seated(self):
        """The whole trial timed, once the patient walked and has sat for ``SEATED_FOR``; the
        fit is tried again at most every ``SEATED_FOR`` (it costs up to 0.2 s)."""
        now = self.samples[-1].t
        if not self.walked or now - self.last_up < SEATED_FOR or now - self.tried < SEATED_FOR:
            return None
        self.tried = now
        try:
            return time_trial(self.samples, 0.0, holes_judged=True)
        except NotATrial:
            return None

    def _result_tx(self, timed) -> dict[str, Any]:
        tug = round(timed.tug_seconds, 2)
        self.phase = "done"
        return self._tx(
            {
                "status": "timed",
                "phase": "done",
                "tug_seconds": tug,
                "phase_seconds": [round(timed.phases[p], 2) for p in PHASES],
                "band": band(tug),
                "fall_risk": fall_risk(tug),
            }
        )

    def _tx(self, attrs: dict[str, Any]) -> dict[str, Any]:
        """Written only to the trial it is about, still being timed (compare-and-set)."""
        return {
            "preconditions": [
                {"check": "attr_equals", "node": "gait", "attr": "trial", "value": self.trial},
                {"check": "attr_equals", "node": "gait", "attr": "status", "value": "timing"},
            ],
            "ops": [{"op": "set_node_attrs", "node": "gait", "attrs": attrs}],
        }
