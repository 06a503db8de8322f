"""The simulated patient's body during a Get Up & Go trial (pure): where each joint is at a time
after "go", following the scenario's motion script.

The trial's frame: origin on the floor under the front of the chair's seat, x along the walk
(the 3 m line), z up. The patient sits facing +x, waits ``reaction`` s, rises (the pelvis goes
up and forward), walks out 3 m with alternating leg swing, turns 180 degrees, walks back, and
sits (turning round again while the pelvis goes down and back). Each movement eases in and out
(smoothstep), as a person's does; between movements the body is still, apart from noise.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from clarc_agents.gug.phases import PHASES

SEATED_PELVIS = 0.47  # m above the floor
STANDING_PELVIS = 0.95
SEATED_X = -0.15  # the pelvis over the seat, behind its front edge
STANDING_X = 0.15  # where the pelvis is once up: in front of the seat
WALK = 3.0  # m, out and back
THIGH = 0.45
SHIN = 0.45
HIP_HALF = 0.10
SHOULDER_HALF = 0.18
STEP_HZ = 0.9  # strides per second of each leg
SWING = 0.25  # m an ankle swings ahead of / behind the pelvis while walking


def smoothstep(u: float) -> float:
    u = min(max(u, 0.0), 1.0)
    return u * u * (3.0 - 2.0 * u)


@dataclass(frozen=True)
class Motion:
    """Seconds of each part of the trial, in the patient's time (the scenario's ``motion:``)."""

    reaction: float
    rise: float
    walk_out: float
    turn: float
    walk_back: float
    sit: float

    @property
    def total(self) -> float:
        """The truth a Timed Up and Go measures: from "go" until seated again."""
        return self.reaction + self.rise + self.walk_out + self.turn + self.walk_back + self.sit

    def starts(self) -> dict[str, float]:
        """When each phase starts, in seconds after "go"."""
        t, starts = self.reaction, {}
        for phase in PHASES:
            starts[phase] = t
            t += getattr(self, phase)
        return starts


@dataclass(frozen=True)
class Body:
    """Where the body is: pelvis position, heading (rad about z), how far up (0 seated, 1
    standing) and how far the legs are through their stride (None: not walking)."""

    pelvis: tuple[float, float, float]
    heading: float
    up: float
    stride: float | None


def body_at(motion: Motion, t: float) -> Body:
    """The body ``t`` seconds after "go" (before it: seated; after the trial: seated)."""
    s = motion.starts()
    if t < s["rise"]:
        return _seated(0.0)
    if t < s["walk_out"]:
        u = smoothstep((t - s["rise"]) / motion.rise)
        x = SEATED_X + (STANDING_X - SEATED_X) * u
        return Body((x, 0.0, _height(u)), 0.0, u, None)
    if t < s["turn"]:
        u = smoothstep((t - s["walk_out"]) / motion.walk_out)
        return Body((STANDING_X + WALK * u, 0.0, STANDING_PELVIS), 0.0, 1.0, t - s["walk_out"])
    far = STANDING_X + WALK
    if t < s["walk_back"]:
        u = smoothstep((t - s["turn"]) / motion.turn)
        return Body((far, 0.0, STANDING_PELVIS), math.pi * u, 1.0, None)
    if t < s["sit"]:
        u = smoothstep((t - s["walk_back"]) / motion.walk_back)
        return Body((far - WALK * u, 0.0, STANDING_PELVIS), math.pi, 1.0, t - s["walk_back"])
    if t < motion.total:
        # turning round to the chair while going down onto it
        u = smoothstep((t - s["sit"]) / motion.sit)
        x = STANDING_X + (SEATED_X - STANDING_X) * u
        return Body((x, 0.0, _height(1.0 - u)), math.pi * (1.0 + u), 1.0 - u, None)
    return _seated(2.0 * math.pi)


def _seated(heading: float) -> Body:
    return Body((SEATED_X, 0.0, SEATED_PELVIS), heading, 0.0, None)


def _height(up: float) -> float:
    return SEATED_PELVIS + (STANDING_PELVIS - SEATED_PELVIS) * up


def joints(body: Body) -> dict[str, np.ndarray]:
    """Every joint of ``body`` in the trial's frame (metres)."""
    pelvis = np.array(body.pelvis)
    forward = np.array([math.cos(body.heading), math.sin(body.heading), 0.0])
    left = np.array([-math.sin(body.heading), math.cos(body.heading), 0.0])
    up = np.array([0.0, 0.0, 1.0])
    # the trunk leans forward while the weight moves over the feet, most half-way up
    lean = 0.35 * math.sin(math.pi * body.up) * forward
    trunk = (up * 0.9 + lean) / np.linalg.norm(up * 0.9 + lean)
    out = {
        "pelvis": pelvis,
        "spine": pelvis + 0.25 * trunk,
        "neck": pelvis + 0.50 * trunk,
        "head": pelvis + 0.65 * trunk,
    }
    out["shoulder_left"] = out["neck"] - 0.05 * up + SHOULDER_HALF * left
    out["shoulder_right"] = out["neck"] - 0.05 * up - SHOULDER_HALF * left
    # thighs from forward (seated) to down (standing); shins down
    thigh_angle = -0.5 * math.pi * body.up
    thigh = math.cos(thigh_angle) * forward + math.sin(thigh_angle) * up
    for side, sign in (("left", 1.0), ("right", -1.0)):
        hip = pelvis + sign * HIP_HALF * left
        swing = 0.0
        if body.stride is not None:  # the legs swing in turn, half a stride apart
            phase = 2.0 * math.pi * STEP_HZ * body.stride + (0.0 if sign > 0 else math.pi)
            swing = SWING * math.sin(phase)
        knee = hip + THIGH * thigh + 0.5 * swing * forward
        ankle = knee - SHIN * up + 0.5 * swing * forward
        if body.up < 1.0:  # seated or getting up: the feet stay on the floor
            ankle[2] = max(ankle[2], 0.08)
        out[f"hip_{side}"] = hip
        out[f"knee_{side}"] = knee
        out[f"ankle_{side}"] = ankle
        out[f"foot_{side}"] = ankle + 0.15 * forward - 0.05 * up
    return out
