"""The gait analyser's logic (pure): it sees only the DSR. While PELEA's ``gait`` node says a
trial is being timed (``status: timing``, ``go_at``, ``trial``), every new skeleton frame of the
person becomes a sample in the Get Up & Go chair's frame (the kinematic chain ``gug_chair`` ->
``kinect`` applied to the joints the sensor trusts): read from the person's
``skeleton_frames`` in the deltas, so that every frame the sensor gave counts, however many a
delta carries (``skeleton.frames_in``; after a resynchronisation, the frames of the person's
last write). The phase in progress is written as it changes, and once the patient has walked
and is seated again the whole trial is timed (``phases.time_trial``, with the line at the
chair's ``line_m``, 3 m by default) and written back: ``tug_seconds``, ``reaction_seconds``,
``phase_seconds`` (in ``PHASES`` order), ``still_seconds``, ``band``, ``fall_risk``,
``status: timed``; or ``status: void`` with the ``reason`` (a hole in the frames, not seated at
go, the line not reached, no turn, not risen within ``RISE_WITHIN`` (30 s) or not seated again
within ``WITHIN`` (90 s) of go). Times are the frames' capture stamps (epoch seconds) turned
into the patient's time with ``scale`` (the session's pace), so a result is the same at any
pace and however late the frames came.
"""

from __future__ import annotations

from collections.abc import Iterator
from typing import Any

from clarc_agents.exceptions import InvalidTrial
from clarc_agents.gug.phases import (
    LINE,
    MAX_GAP,
    MIN_RISE,
    PHASES,
    RISE_WITHIN,
    WITHIN,
    NotATrial,
    Sample,
    band,
    fall_risk,
    half_turn_step,
    sample,
    time_trial,
)
from clarc_agents.gug.skeleton import SENSOR, frames_in, frames_on
from dsr_graph.exceptions import DsrError
from dsr_graph.model.graph import Graph

CHAIR = "gug_chair"
WATCHED = ("pelvis", "hip_left", "hip_right", "shoulder_left", "shoulder_right")
SEATED_FOR = 1.0  # s of the patient's time seated again before the trial is timed
ORDER = ("waiting", *PHASES, "done")
FAR = 1.0  # m from the chair: the patient walked (whether far enough is the trial's judgement)


class GaitAnalyser:
    def __init__(self, scale: float = 1.0):
        self.scale = scale or 1.0
        self.trial: Any = None
        self.go = 0.0
        self.samples: list[Sample] = []
        self.phase = ""
        self._last_frame = None
        self.line = LINE
        self._reset()

    def _reset(self) -> None:
        """What is followed of the trial as frames come, so each frame costs the same."""
        self.samples = []
        self.walked = False  # the hips have been FAR from the chair
        self.low = self.high = None  # the lowest and highest hips so far
        self.turned = 0.0  # rad the body turned since go
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
            chair = graph.find(CHAIR)
            self.line = float(chair.attrs.get("line_m", LINE)) if chair is not None else LINE
            self._reset()
        frames = (
            [f for delta in deltas for f in frames_in(delta)]
            if deltas is not None
            else frames_on(graph)
        )
        news = self._samples(graph, frames)
        tx = None
        for new in news:  # each frame taken, then judged, before the next is taken
            if self.phase == "done":
                break
            if new is not None:
                tx = self._on_sample(new) or tx  # a later write says what an earlier would
        return tx

    def _on_sample(self, new: Sample) -> dict[str, Any] | None:
        before = self.samples[-2].t if len(self.samples) > 1 else 0.0  # "go"
        # every frame the sensor gave reaches the DSR (Person writes them all, several at a
        # time when it is behind), and times are the frames' capture stamps: a hole here is the
        # sensor's own (the person out of view, the Kinect or Person down), never a late frame
        if new.t - before > MAX_GAP:
            return self._void(
                f"no frames for {new.t - before:.1f} s from {before:.1f} s after go: "
                "the trial cannot be timed"
            )
        timed = self._time_if_seated()
        if isinstance(timed, str):
            return self._void(timed)
        if timed is not None:
            return self._result_tx(timed)
        # judged on the frames' stamps, so a busy machine never voids a trial
        if new.t > RISE_WITHIN and self.phase == "waiting":
            return self._void(f"did not rise within {RISE_WITHIN:g} s of go")
        if new.t > WITHIN:
            return self._void(f"not seated again within {WITHIN:g} s of go")
        phase = self._phase_now()
        # the phase in progress only moves on (noise must not make it flicker back)
        if ORDER.index(phase) > ORDER.index(self.phase):
            self.phase = phase
            return self._tx({"phase": phase})
        return None

    def _void(self, reason: str) -> dict[str, Any]:
        self.phase = "done"
        return self._tx({"status": "void", "phase": "done", "reason": reason})

    # ------------------------------------------------------------------ samples
    def _samples(self, graph: Graph, frames) -> Iterator[Sample | None]:
        """A sample per new frame, in order (taken one at a time): the watched joints the
        sensor trusts, in the chair's frame (the kinematic chain chair -> kinect)."""
        if not frames or graph.find(CHAIR) is None:
            return
        try:
            chair_kinect = graph.transform(CHAIR, SENSOR)
        except DsrError:
            return
        rotation, offset = chair_kinect[:3, :3], chair_kinect[:3, 3]
        for stamp, joints in frames:
            if self._last_frame is not None and stamp <= self._last_frame:
                continue
            self._last_frame = stamp
            seen = {j: rotation @ joints[j][0] + offset for j in WATCHED if j in joints}
            trust = {j: joints[j][1] for j in WATCHED if j in joints}
            yield self._add(stamp, seen, trust)

    def _add(self, frame: float, joints: dict[str, Any], trust: dict[str, float]) -> Sample | None:
        """The sample of a frame (its time, the watched joints in the chair's frame), kept
        when it comes after "go"."""
        s = sample((float(frame) - self.go) / self.scale, joints, trust)
        if s is None or s.t < 0.0:
            return None
        if self.samples:  # a left/right swap is no turn
            self.turned += half_turn_step(self.samples[-1].heading, s.heading)
        self.samples.append(s)
        self.walked = self.walked or s.distance > FAR
        self.low = s.height if self.low is None else min(self.low, s.height)
        self.high = s.height if self.high is None else max(self.high, s.height)
        if s.height > self.low + 0.3 * max(self.high - self.low, MIN_RISE):
            self.last_up = s.t
        return s

    # ------------------------------------------------------------------ the trial
    def _phase_now(self) -> str:
        """The phase in progress, roughly (for those who watch; the timing is done at the
        end): how far up and out the patient is and how far they turned."""
        last, seated = self.samples[-1], self.low
        turned = abs(self.turned)
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
        """The whole trial timed, once the patient walked and has sat for ``SEATED_FOR``
        (tried again at most every ``SEATED_FOR``); the reason, when the trial does not count
        (not seated at go, the line not reached, no turn)."""
        now = self.samples[-1].t
        if not self.walked or now - self.last_up < SEATED_FOR or now - self.tried < SEATED_FOR:
            return None
        self.tried = now
        try:
            return time_trial(self.samples, 0.0, holes_judged=True, line=self.line)
        except InvalidTrial as e:
            return str(e)
        except NotATrial:
            return None

    def _result_tx(self, timed) -> dict[str, Any]:
        tug = round(timed.tug_seconds, 2)
        phases = [round(timed.phases[p], 2) for p in PHASES]
        still = round(timed.still, 2)
        # the parts add up to the total as stored, rounding included: the reaction takes it
        reaction = round(tug - sum(phases) - still, 2)
        self.phase = "done"
        return self._tx(
            {
                "status": "timed",
                "phase": "done",
                "tug_seconds": tug,
                "reaction_seconds": reaction,
                "phase_seconds": phases,
                "still_seconds": still,
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
