"""What the Kinect stand-in sees of the patient during a Get Up & Go trial (pure): the joints of
``gait_motion`` moved into the Kinect's frame, in millimetres (its SDK's unit), with a tracking
confidence each, sensor noise and lost frames."""

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


def skeleton(
    motion: Motion,
    t: float,
    place: TrialPlace,
    rng: random.Random,
    noise_mm: float = 0.0,
) -> dict[str, dict[str, object]]:
    """The joints ``t`` seconds after "go" (negative: still waiting, seated): {joint: {"p": [x,
    y, z] mm, "c": confidence}}."""
    out = {}
    for name, p in joints(body_at(motion, t)).items():
        x, y, z = place.to_kinect(p)
        if noise_mm > 0:
            x, y, z = (v + rng.gauss(0.0, noise_mm) for v in (x, y, z))
        out[name] = {
            "p": [round(x, 1), round(y, 1), round(z, 1)],
            "c": round(rng.uniform(0.8, 1.0), 2),
        }
    return out


def recorded(
    recording,
    t: float,
    place: TrialPlace,
    rng: random.Random,
    noise_mm: float = 0.0,
) -> dict[str, dict[str, object]] | None:
    """The frame of a placed recording (``skeleton_recording.placed``) shown ``t`` seconds
    into it, as ``skeleton`` gives a frame; None when it has no pelvis (no body)."""
    i = recording.frame_at(t)
    out = {}
    for j, name in enumerate(recording.joints):
        c = float(recording.confidence[i, j])
        if c <= 0.0:
            continue
        x, y, z = place.to_kinect(recording.positions[i, j])
        if noise_mm > 0:
            x, y, z = (v + rng.gauss(0.0, noise_mm) for v in (x, y, z))
        out[name] = {"p": [round(x, 1), round(y, 1), round(z, 1)], "c": round(c, 2)}
    return out if "pelvis" in out else None


def dropped(rng: random.Random, drop_rate: float) -> bool:
    return drop_rate > 0 and rng.random() < drop_rate
