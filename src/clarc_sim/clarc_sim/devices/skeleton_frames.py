"""What the Kinect stand-in sees of the patient during a Get Up & Go trial (pure): the joints of
``gait_motion`` or of a recording moved into the Kinect's frame, in millimetres (its SDK's unit),
then what a Kinect v2 makes of them (``KinectModel``: slow noise, confidence falling with range
and occlusion, the sides swapped when the body faces away), and lost frames."""

from __future__ import annotations

import math
import random
from dataclasses import dataclass

from clarc_sim.patient.gait_motion import Motion, body_at, joints


@dataclass(frozen=True)
class TrialPlace:
    """Where the trial's frame is in the Kinect's: the floor under the chair's front, in mm, and
    the walk's direction (yaw about the vertical, rad)."""

    x: float
    y: float
    z: float
    yaw: float

    def to_kinect(self, p) -> list[float]:
        c, s = math.cos(self.yaw), math.sin(self.yaw)
        x, y, z = (float(v) * 1000.0 for v in p)
        return [self.x + c * x - s * y, self.y + s * x + c * y, self.z + z]


LEFT_RIGHT = (
    ("shoulder_left", "shoulder_right"),
    ("hip_left", "hip_right"),
    ("knee_left", "knee_right"),
    ("ankle_left", "ankle_right"),
    ("foot_left", "foot_right"),
)
RANGE = 4.5  # m: a Kinect v2 tracks bodies up to this far, less surely beyond
SURE_WITHIN = 3.5  # m: closer than this, distance costs no confidence
NOISE_TAU = 0.1  # s: how long a joint's error lasts (a Kinect's noise is slow, not per frame)
OCCLUDED_NOISE = 1.5  # times the noise of a joint the body hides from the sensor
JITTER = 0.3  # of the noise: what is new in each frame


def skeleton(motion: Motion, t: float, place: TrialPlace) -> dict[str, dict[str, object]]:
    """The body's joints ``t`` seconds after "go" (negative: still waiting, seated), as a
    perfect sensor would give them: {joint: {"p": [x, y, z] mm, "c": 1.0}}."""
    return {
        name: {"p": place.to_kinect(p), "c": 1.0} for name, p in joints(body_at(motion, t)).items()
    }


def recorded(recording, t: float, place: TrialPlace) -> dict[str, dict[str, object]] | None:
    """The frame of a placed recording (``skeleton_recording.placed``) shown ``t`` seconds
    into it, as ``skeleton`` gives a frame (the recording's confidences); None when it has no
    pelvis (no body)."""
    i = recording.frame_at(t)
    out = {}
    for j, name in enumerate(recording.joints):
        c = float(recording.confidence[i, j])
        if c > 0.0:
            out[name] = {"p": place.to_kinect(recording.positions[i, j]), "c": c}
    return out if "pelvis" in out else None


class KinectModel:
    """What a Kinect v2 makes of a body it sees (stateful: its errors last a while).

    - Noise: each joint's error follows a first-order process with a time constant of
      ``NOISE_TAU`` (standard deviation ``noise_mm``), plus a little jitter per frame.
    - Confidence: 1 within ``SURE_WITHIN`` of the sensor, falling to 0.8 at ``RANGE`` and 0.6
      beyond it (and a range warning); the joints on the far side of a body seen side-on are
      occluded: half as sure, half as noisy again.
    - Facing away from the sensor, the body's sides are swapped (left joints reported as the
      right ones), as a Kinect's skeleton tracker does.
    """

    def __init__(self, rng: random.Random, noise_mm: float = 0.0):
        self.rng, self.noise_mm = rng, noise_mm
        self._errors: dict[str, list[float]] = {}
        self._last: float | None = None

    def see(self, ideal: dict[str, dict[str, object]], t: float) -> tuple[dict, bool]:
        """(the frame's joints, beyond the range) for the ``ideal`` joints at ``t`` s."""
        step = 1.0 if self._last is None else max(0.0, t - self._last)
        self._last = t
        keep = math.exp(-step / NOISE_TAU)
        pelvis = ideal["pelvis"]["p"]
        distance = math.hypot(pelvis[0], pelvis[1]) / 1000.0
        sure = _range_confidence(distance)
        facing, far_side = _facing(ideal)
        out = {}
        for name, joint in ideal.items():
            occluded = far_side is not None and name.endswith(far_side)
            sigma = self.noise_mm * (OCCLUDED_NOISE if occluded else 1.0)
            error = self._errors.get(name, [0.0, 0.0, 0.0])
            error = [
                keep * e + math.sqrt(1.0 - keep * keep) * self.rng.gauss(0.0, sigma) for e in error
            ]
            self._errors[name] = error
            p = [
                v + e + self.rng.gauss(0.0, JITTER * sigma)
                for v, e in zip(joint["p"], error, strict=True)
            ]
            c = float(joint["c"]) * sure * (0.5 if occluded else 1.0)
            out[name] = {"p": [round(v, 1) for v in p], "c": round(c, 2)}
        if facing < -0.2:  # its back to the sensor: the tracker takes the left for the right
            for left, right in LEFT_RIGHT:
                if left in out and right in out:
                    out[left], out[right] = out[right], out[left]
        return out, distance > RANGE


def _range_confidence(distance: float) -> float:
    if distance <= SURE_WITHIN:
        return 1.0
    if distance <= RANGE:
        return 1.0 - 0.2 * (distance - SURE_WITHIN) / (RANGE - SURE_WITHIN)
    return 0.6


def _facing(ideal: dict[str, dict[str, object]]) -> tuple[float, str | None]:
    """(how much the body faces the sensor, -1 to 1; the side turned away when it is seen
    side-on, "left" or "right", else None), from its hips and shoulders."""
    lefts = [
        [a - b for a, b in zip(ideal[left]["p"][:2], ideal[right]["p"][:2], strict=True)]
        for left, right in LEFT_RIGHT[:2]
        if left in ideal and right in ideal
    ]
    pelvis = ideal["pelvis"]["p"]
    to_sensor = [-pelvis[0], -pelvis[1]]
    norm = math.hypot(*to_sensor)
    if not lefts or norm == 0.0:
        return 1.0, None
    left = [sum(v[i] for v in lefts) for i in range(2)]
    size = math.hypot(*left) or 1.0
    left = [left[0] / size, left[1] / size]
    to_sensor = [to_sensor[0] / norm, to_sensor[1] / norm]
    forward = [left[1], -left[0]]  # the body faces 90 degrees from its left, turned the other way
    facing = forward[0] * to_sensor[0] + forward[1] * to_sensor[1]
    if abs(facing) >= 0.5:
        return facing, None
    left_towards = left[0] * to_sensor[0] + left[1] * to_sensor[1]
    return facing, "left" if left_towards < 0 else "right"


def tracking_losses(rng: random.Random, count: int, length: float) -> list[tuple[float, float]]:
    """``count`` brief spells (0.1 to 0.35 s of the patient's time) in which the tracker loses
    the body, at random within a trial of ``length`` s (not in its first and last second)."""
    spells = []
    for _ in range(count):
        start = rng.uniform(1.0, max(1.0, length - 1.0))
        spells.append((start, start + rng.uniform(0.1, 0.35)))
    return sorted(spells)


def dropped(rng: random.Random, drop_rate: float) -> bool:
    return drop_rate > 0 and rng.random() < drop_rate
