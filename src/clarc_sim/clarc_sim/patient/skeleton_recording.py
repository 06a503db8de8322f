"""Recorded human movement for the Kinect stand-in to play (pure): CLARC's skeleton-recording
file, and placing a recording in a Get Up & Go trial.

The file (CSV, written by ``clarc skeleton import``; docs/FORMAT.md):

    # clarc-skeleton 1
    t,pelvis_x,pelvis_y,pelvis_z,pelvis_c,head_x,...
    0.0000,0.712,0.669,0.551,1,...

``t`` is seconds from the recording's start, increasing; each joint of the header (any of
``gug.skeleton.JOINTS``, the pelvis among them) has four columns: x, y, z in metres, z up with
the floor at z = 0, and a tracking confidence from 0 to 1. Empty cells: the joint was not
tracked in that frame; a row with every joint empty is a frame without a body.

A recording is placed in the trial's frame (``gait_motion``'s: the floor under the chair's
front, x along the walk, z up) by a turn about the vertical and a shift on the floor: the
seated pelvis (its first half second) goes where the simulated patient's sits, ``SEATED_X``
behind the chair's front on its middle line, and the first walk (from there to the farthest
the pelvis gets) goes along +x. Heights are kept.
"""

from __future__ import annotations

import csv
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from clarc_agents.gug.skeleton import JOINTS
from clarc_sim.exceptions import SkeletonRecordingError
from clarc_sim.patient.gait_motion import SEATED_X

MAGIC = "# clarc-skeleton 1"
SEATED_SPELL = 0.5  # s at the start of a recording the patient sits


@dataclass(frozen=True)
class Recording:
    t: np.ndarray  # (frames,) seconds from the start
    joints: tuple[str, ...]
    positions: np.ndarray  # (frames, joints, 3) metres; NaN: not tracked
    confidence: np.ndarray  # (frames, joints) 0..1; 0: not tracked

    @property
    def duration(self) -> float:
        return float(self.t[-1] - self.t[0]) if len(self.t) else 0.0

    def joint(self, name: str) -> np.ndarray:
        return self.positions[:, self.joints.index(name)]

    def frame_at(self, t: float) -> int:
        """The frame shown at ``t`` s from the start: the last one taken at or before it (the
        first before the start, the last after the end)."""
        return max(0, int(np.searchsorted(self.t, self.t[0] + t, side="right")) - 1)


def write(recording: Recording, path: str | Path) -> None:
    with open(path, "w", encoding="utf-8", newline="") as f:
        f.write(MAGIC + "\n")
        out = csv.writer(f, lineterminator="\n")
        out.writerow(["t", *(f"{j}_{k}" for j in recording.joints for k in "xyzc")])
        for i, t in enumerate(recording.t):
            row = [f"{t:.4f}"]
            for j in range(len(recording.joints)):
                p, c = recording.positions[i, j], recording.confidence[i, j]
                if np.isnan(p).any() or c <= 0.0:
                    row += ["", "", "", ""]
                else:
                    row += [f"{v:.4f}" for v in p] + [f"{c:.3g}"]
            out.writerow(row)


def csv_rows(path: str | Path, kind: str) -> list[list[str]]:
    """The rows of the CSV file ``path`` (a ``kind``, for the error)."""
    try:
        with open(path, encoding="utf-8", newline="") as f:
            return list(csv.reader(f))
    except OSError as e:
        raise SkeletonRecordingError(f"{path}: cannot read: {e.strerror}") from None
    except (UnicodeDecodeError, csv.Error) as e:
        raise SkeletonRecordingError(f"{path}: not {kind} ({e})") from None


def read(path: str | Path) -> Recording:
    """The recording in ``path``; ``SkeletonRecordingError`` naming the line and what is wrong."""
    lines = csv_rows(path, "a skeleton recording")
    if not lines or lines[0] != [MAGIC]:
        raise SkeletonRecordingError(f"{path}:1: a skeleton recording starts with {MAGIC!r}")
    if len(lines) < 3:
        raise SkeletonRecordingError(f"{path}: no frames")
    joints = _header(path, lines[1])
    t, positions, confidence = [], [], []
    for number, row in enumerate(lines[2:], start=3):
        where = f"{path}:{number}"
        if len(row) != 1 + 4 * len(joints):
            raise SkeletonRecordingError(
                f"{where}: {len(row)} cells, the header has {1 + 4 * len(joints)}"
            )
        time = _float(where, "t", row[0])
        if t and time <= t[-1]:
            raise SkeletonRecordingError(f"{where}: t {time} does not come after {t[-1]}")
        t.append(time)
        p, c = np.full((len(joints), 3), np.nan), np.zeros(len(joints))
        for j, joint in enumerate(joints):
            cells = row[1 + 4 * j : 5 + 4 * j]
            if not any(cells):
                continue
            if not all(cells):
                raise SkeletonRecordingError(f"{where}: {joint} has some of x, y, z, c empty")
            p[j] = [_float(where, f"{joint}_{k}", v) for k, v in zip("xyz", cells, strict=False)]
            c[j] = _float(where, f"{joint}_c", cells[3])
            if not 0.0 <= c[j] <= 1.0:
                raise SkeletonRecordingError(
                    f"{where}: {joint}_c {c[j]} is not a confidence (0..1)"
                )
        positions.append(p)
        confidence.append(c)
    return Recording(np.array(t), joints, np.array(positions), np.array(confidence))


def _header(path, row: list[str]) -> tuple[str, ...]:
    if not row or row[0] != "t" or (len(row) - 1) % 4:
        raise SkeletonRecordingError(f"{path}:2: the header is t, then x, y, z, c of each joint")
    joints = []
    for i in range(1, len(row), 4):
        joint = row[i][: -len("_x")]
        if row[i : i + 4] != [f"{joint}_{k}" for k in "xyzc"]:
            raise SkeletonRecordingError(
                f"{path}:2: expected {joint}_x, {joint}_y, {joint}_z, {joint}_c"
            )
        if joint not in JOINTS:
            raise SkeletonRecordingError(
                f"{path}:2: unknown joint {joint!r}; the joints are {JOINTS}"
            )
        joints.append(joint)
    if "pelvis" not in joints:
        raise SkeletonRecordingError(f"{path}:2: a recording without the pelvis cannot be placed")
    return tuple(joints)


def _float(where: str, what: str, text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise SkeletonRecordingError(f"{where}: {what} {text!r} is not a number") from None
    if not math.isfinite(value):
        raise SkeletonRecordingError(f"{where}: {what} must be finite, got {text!r}")
    return value


def placed(recording: Recording) -> Recording:
    """``recording`` in the trial's frame: the seated pelvis at the chair, the first walk along
    +x (see the module's text); ``SkeletonRecordingError`` if it has no seated start or no walk."""
    pelvis = recording.joint("pelvis")
    seated = (recording.t - recording.t[0] < SEATED_SPELL) & ~np.isnan(pelvis[:, 0])
    if not seated.any():
        raise SkeletonRecordingError(
            "the pelvis is not tracked in the recording's first half second"
        )
    start = np.mean(pelvis[seated], axis=0)
    away = np.hypot(pelvis[:, 0] - start[0], pelvis[:, 1] - start[1])
    if np.all(np.isnan(away)) or np.nanmax(away) < 1.0:
        raise SkeletonRecordingError(
            "the pelvis never goes 1 m from where it sits: no walk to place"
        )
    far = pelvis[int(np.nanargmax(away))]
    yaw = math.atan2(far[1] - start[1], far[0] - start[0])
    c, s = math.cos(-yaw), math.sin(-yaw)
    turn = np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])
    shift = np.array([SEATED_X, 0.0, 0.0]) - turn @ np.array([start[0], start[1], 0.0])
    positions = recording.positions @ turn.T + shift
    return Recording(recording.t, recording.joints, positions, recording.confidence)


FEET = ("foot_left", "foot_right", "ankle_left", "ankle_right")


def floor_at_zero(positions: np.ndarray, joints: tuple[str, ...]) -> np.ndarray:
    """``positions`` (frames, joints, 3; z up) moved up or down so the floor is at z = 0: where
    the lowest foot or ankle usually is (the 2nd percentile over the recording of each frame's
    lowest). A recording without feet or ankles is left as it is."""
    feet = [joints.index(j) for j in FEET if j in joints]
    if not feet:
        return positions
    heights = positions[:, feet, 2]
    if np.isnan(heights).all():
        return positions
    lowest = np.min(np.where(np.isnan(heights), np.inf, heights), axis=1)
    lowest = lowest[np.isfinite(lowest)]
    return positions - np.array([0.0, 0.0, float(np.percentile(lowest, 2))])
