"""Timing a Get Up & Go trial from the patient's joints (pure; the gait analyser feeds it what
the DSR shows, in the chair's frame: x, y on the floor from the chair, z up, metres).

Three signals tell the whole trial: the height of the hips above the floor (up when rising,
down when sitting), their distance from the chair (out and back), and the heading of the body
from the line through the hips and the shoulders (half a turn at the far end). Each movement is
a transition between two still plateaus; it is located by a least-squares fit of an eased step
(``smoothstep``) to the signal in a window that holds only that movement, which puts its start
and end within a frame or two even with noisy joints and dropped frames. Where two movements
meet, the boundary is half-way between the end of one and the start of the next.

    phases = time_trial(samples, go)   # Samples after "go" until seated again
    phases.tug_seconds, phases.phases["turn"], band(phases.tug_seconds)
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from clarc_agents.exceptions import NotATrial, TrialGap

PHASES = ("rise", "walk_out", "turn", "walk_back", "sit")
HIPS = ("pelvis", "hip_left", "hip_right")
SIDES = (("hip_left", "hip_right"), ("shoulder_left", "shoulder_right"))
COARSE = 0.1  # s, the first grid of a fit
FINE = 1.0 / 60.0  # s, the grid it is refined on
MIN_MOVE = 0.2  # s: no movement of a trial is shorter
MAX_GAP = 0.5  # s without a frame that a trial may have (lost frames leave 0.1 s or so)


@dataclass(frozen=True)
class Sample:
    t: float  # seconds (of the patient's time)
    height: float  # of the hips above the floor
    distance: float  # of the hips from the chair, on the floor
    heading: float  # rad about the vertical, from the hips and shoulders


def sample(t: float, joints: dict[str, Sequence[float]]) -> Sample | None:
    """A sample from the joints of one frame (in the chair's frame); None without the hips."""
    hips = [np.asarray(joints[j], dtype=float) for j in HIPS if j in joints]
    if not hips:
        return None
    centre = np.mean(hips, axis=0)
    lefts = [
        np.asarray(joints[a], dtype=float) - np.asarray(joints[b], dtype=float)
        for a, b in SIDES
        if a in joints and b in joints
    ]
    if not lefts:
        return None
    left = np.mean(lefts, axis=0)
    # the body faces +90 degrees from its left-to-right line, turned the other way
    heading = math.atan2(-left[0], left[1])
    return Sample(t, float(centre[2]), float(math.hypot(centre[0], centre[1])), heading)


@dataclass(frozen=True)
class TrialTimes:
    go: float
    boundaries: tuple[float, ...]  # start of rise, the four meetings, seated again

    @property
    def tug_seconds(self) -> float:
        return self.boundaries[-1] - self.go

    @property
    def reaction(self) -> float:
        return self.boundaries[0] - self.go

    @property
    def phases(self) -> dict[str, float]:
        b = self.boundaries
        return {p: b[i + 1] - b[i] for i, p in enumerate(PHASES)}


def band(tug_seconds: float) -> str:
    """Podsiadlo & Richardson (1991)."""
    if tug_seconds < 10.0:
        return "normal"
    if tug_seconds < 20.0:
        return "mostly independent"
    if tug_seconds < 30.0:
        return "variable mobility"
    return "impaired mobility"


def fall_risk(tug_seconds: float) -> bool:
    """Shumway-Cook, Brauer & Woollacott (2000): 13.5 s or more."""
    return tug_seconds >= 13.5


def time_trial(samples: Sequence[Sample], go: float, holes_judged: bool = False) -> TrialTimes:
    """The boundaries of the phases of the trial that began at ``go``. ``holes_judged``: the
    caller has judged every gap between the samples as they came (the gait analyser, which
    knows from Person's ``sensor_gap`` which gaps the sensor itself had), so none is checked
    again here."""
    samples = sorted((s for s in samples if s.t >= go), key=lambda s: s.t)
    if len(samples) < 30:
        raise NotATrial(f"{len(samples)} frames after go: too few for a trial")
    t = np.array([s.t for s in samples])
    if not holes_judged:
        check_gaps(t, go)
    height = np.array([s.height for s in samples])
    distance = np.array([s.distance for s in samples])
    heading = np.unwrap(np.array([s.heading for s in samples]))
    heading -= heading[0]

    low, high = np.percentile(height, 5), np.percentile(height, 95)
    if high - low < 0.2:
        raise NotATrial(f"the hips rose {high - low:.2f} m: the patient did not stand up")
    up = np.flatnonzero(height > (low + high) / 2)
    t_down = t[up[-1]]
    far = np.percentile(distance, 95)
    if far < 1.5:
        raise NotATrial(f"the patient went {far:.1f} m from the chair: no walk")
    out = np.flatnonzero(distance > far / 2)
    t_out, t_back = t[out[0]], t[out[-1]]
    if t[-1] - t_down < 0.5 or t[-1] <= t_back or t[0] >= t_out:
        raise NotATrial("not seated again yet")
    if abs(np.median(heading[t > t_back]) - np.median(heading[t < t_out])) < 0.5 * math.pi:
        raise NotATrial("the patient did not turn round")

    rise = _fit_step(t, height, go, t_out)
    sit = _fit_step(t, height, t_back, t[-1])
    turn = _fit_step(t, heading, t_out, t_back)
    walk_out = _fit_step(t, distance, rise[1], turn[0])
    walk_back = _fit_step(t, distance, turn[1], sit[0])
    moves = (rise, walk_out, turn, walk_back, sit)
    meetings = tuple((a[1] + b[0]) / 2 for a, b in zip(moves, moves[1:], strict=False))
    return TrialTimes(go, (rise[0], *meetings, sit[1]))


def check_gaps(t: np.ndarray, go: float) -> None:
    """``TrialGap`` if the frames from ``go`` on leave a hole longer than ``MAX_GAP``."""
    steps = np.diff(np.concatenate(([go], t)))
    worst = int(np.argmax(steps))
    if steps[worst] > MAX_GAP:
        at = go if worst == 0 else t[worst - 1]
        raise TrialGap(
            f"no frames for {steps[worst]:.1f} s from {at - go:.1f} s after go: "
            "the trial cannot be timed"
        )


def _fit_step(t: np.ndarray, y: np.ndarray, lo: float, hi: float) -> tuple[float, float]:
    """(start, end) of the one eased step between plateaus that ``y`` makes in [lo, hi]."""
    inside = (t >= lo) & (t <= hi)
    ts, ys = t[inside], y[inside]
    if len(ts) < 10 or hi - lo < MIN_MOVE:
        raise NotATrial(f"too little of the trial between {lo:.1f} s and {hi:.1f} s")
    starts = np.arange(lo, hi, COARSE)
    lengths = np.arange(MIN_MOVE, hi - lo + COARSE, COARSE)
    best = _best(ts, ys, starts, lengths)
    starts = np.arange(best[0] - 2 * COARSE, best[0] + 2 * COARSE, FINE)
    lengths = np.arange(max(MIN_MOVE, best[1] - 2 * COARSE), best[1] + 2 * COARSE, FINE)
    start, length = _best(ts, ys, starts, lengths)
    return start, start + length


def _best(ts: np.ndarray, ys: np.ndarray, starts: np.ndarray, lengths: np.ndarray):
    """The (start, length) whose eased step explains ``ys`` best (least squares, with the two
    plateaus' levels solved for each)."""
    centred = ys - ys.mean()
    best, found = -1.0, (float(starts[0]), float(lengths[0]))
    for length in lengths:  # one length at a time: starts x samples stays small
        u = np.clip((ts[None, :] - starts[:, None]) / length, 0.0, 1.0)
        model = u * u * (3.0 - 2.0 * u)
        model -= model.mean(axis=1, keepdims=True)
        cov = model @ centred
        var = np.einsum("ij,ij->i", model, model)
        score = np.where(var > 1e-12, cov * cov / np.maximum(var, 1e-12), -1.0)
        i = int(np.argmax(score))
        if score[i] > best:
            best, found = float(score[i]), (float(starts[i]), float(length))
    return found
