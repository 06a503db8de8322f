"""Importing recorded movement into CLARC's skeleton recordings (pure; ``clarc skeleton import``).

Three sources, each mapped to our 14 joints (``gug.skeleton.JOINTS``), turned so z is up
(``--up``: the source's axis that points up), scaled to metres (``--units``), with the floor
moved to z = 0 (``skeleton_recording.floor_at_zero``):

- ``mediapipe33``: MediaPipe Pose's 33 3D landmarks in CSV, ``frame,p1_x,p1_y,p1_z,...,p33_z``
  (``pN`` is landmark N-1), as pose tools write it; a ``time`` column (seconds) if there is one,
  else ``frame`` / ``--fps`` (59.94 by default: the tools' usual video rate). Head: mid-ears;
  neck: mid-shoulders; pelvis: mid-hips; spine: half-way between pelvis and neck; feet: the foot
  index landmarks. No confidences in the file: every landmark given counts as tracked.
  Defaults: up z, metres.
- ``bvh``: BVH motion capture (read with bvhio), world positions of the joints whose names match
  ours (Hips, Spine/Chest, Neck, Head, LeftArm/LeftShoulder, LeftUpLeg, LeftLeg, LeftFoot,
  LeftToeBase and the right ones, case and common variants aside). Defaults: up y, centimetres.
- ``kinect25``: Kinect v2's 25 joints in CSV, a ``time`` column (seconds) or ``frame`` /
  ``--fps`` (30 by default), and ``<JointType>_x``, ``_y``, ``_z`` per joint (SpineBase, Neck,
  HipLeft, ...), with ``<JointType>_state`` (0 not tracked, 1 inferred, 2 tracked) if given:
  inferred joints get confidence 0.5. Defaults: up y, metres.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from pathlib import Path

import numpy as np

from clarc_agents.gug.skeleton import JOINTS
from clarc_sim.exceptions import SkeletonRecordingError
from clarc_sim.patient.skeleton_recording import Recording, csv_rows, floor_at_zero

# rotations taking the source's up axis to +z (right-handed, a turn, never a mirror)
UP = {
    "z": np.eye(3),
    "-z": np.diag([1.0, -1.0, -1.0]),
    "y": np.array([[1.0, 0.0, 0.0], [0.0, 0.0, -1.0], [0.0, 1.0, 0.0]]),
    "-y": np.array([[1.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, -1.0, 0.0]]),
    "x": np.array([[0.0, 0.0, -1.0], [0.0, 1.0, 0.0], [1.0, 0.0, 0.0]]),
    "-x": np.array([[0.0, 0.0, 1.0], [0.0, 1.0, 0.0], [-1.0, 0.0, 0.0]]),
}
UNITS = {"m": 1.0, "cm": 0.01, "mm": 0.001, "in": 0.0254}

MEDIAPIPE = {  # our joint: the landmarks (1-based pN) it is the middle of
    "head": (8, 9),
    "neck": (12, 13),
    "pelvis": (24, 25),
    "shoulder_left": (12,),
    "shoulder_right": (13,),
    "hip_left": (24,),
    "hip_right": (25,),
    "knee_left": (26,),
    "knee_right": (27,),
    "ankle_left": (28,),
    "ankle_right": (29,),
    "foot_left": (32,),
    "foot_right": (33,),
}
KINECT = {
    "head": "head",
    "neck": "spineshoulder",
    "spine": "spinemid",
    "pelvis": "spinebase",
    "shoulder_left": "shoulderleft",
    "shoulder_right": "shoulderright",
    "hip_left": "hipleft",
    "hip_right": "hipright",
    "knee_left": "kneeleft",
    "knee_right": "kneeright",
    "ankle_left": "ankleleft",
    "ankle_right": "ankleright",
    "foot_left": "footleft",
    "foot_right": "footright",
}
BVH = {  # our joint: names it goes by in BVH files, the likeliest first (lower case)
    "pelvis": ("hips", "pelvis", "root"),
    "spine": ("spine1", "spine", "chest", "spine2"),
    "neck": ("neck", "neck1"),
    "head": ("head",),
    "shoulder_left": ("leftarm", "leftshoulder", "lshoulder", "leftuparm", "l_shoulder"),
    "shoulder_right": ("rightarm", "rightshoulder", "rshoulder", "rightuparm", "r_shoulder"),
    "hip_left": ("leftupleg", "lefthip", "lhip", "lthigh", "l_hip"),
    "hip_right": ("rightupleg", "righthip", "rhip", "rthigh", "r_hip"),
    "knee_left": ("leftleg", "leftknee", "lknee", "leftlowleg", "lshin", "l_knee"),
    "knee_right": ("rightleg", "rightknee", "rknee", "rightlowleg", "rshin", "r_knee"),
    "ankle_left": ("leftfoot", "leftankle", "lankle", "lfoot", "l_ankle"),
    "ankle_right": ("rightfoot", "rightankle", "rankle", "rfoot", "r_ankle"),
    "foot_left": ("lefttoebase", "lefttoe", "ltoes", "ltoe", "l_toe"),
    "foot_right": ("righttoebase", "righttoe", "rtoes", "rtoe", "r_toe"),
}
DEFAULTS = {  # up, units, fps
    "mediapipe33": ("z", "m", 59.94),
    "bvh": ("y", "cm", None),
    "kinect25": ("y", "m", 30.0),
}
FORMATS = tuple(DEFAULTS)


def import_recording(
    kind: str,
    path: str | Path,
    up: str | None = None,
    units: str | None = None,
    fps: float | None = None,
) -> Recording:
    """The recording in ``path`` (of ``kind``, one of ``FORMATS``) as CLARC's: our joints, z up,
    metres, the floor at z = 0. ``SkeletonRecordingError`` naming what is wrong."""
    if kind not in DEFAULTS:
        raise SkeletonRecordingError(
            f"unknown format {kind!r}; the formats are {', '.join(FORMATS)}"
        )
    default_up, default_units, default_fps = DEFAULTS[kind]
    up, units, fps = up or default_up, units or default_units, fps or default_fps
    if up not in UP:
        raise SkeletonRecordingError(f"--up must be one of {', '.join(UP)}, got {up!r}")
    if units not in UNITS:
        raise SkeletonRecordingError(f"--units must be one of {', '.join(UNITS)}, got {units!r}")
    if fps is not None and not (math.isfinite(fps) and fps > 0):
        raise SkeletonRecordingError(f"--fps must be a positive number, got {fps!r}")
    t, joints, positions, confidence = READERS[kind](Path(path), fps)
    positions = positions @ UP[up].T * UNITS[units]
    positions = floor_at_zero(positions, joints)
    confidence = np.where(np.isnan(positions).any(axis=2), 0.0, confidence)
    if "pelvis" not in joints or np.isnan(positions[:, joints.index("pelvis"), 0]).all():
        raise SkeletonRecordingError(f"{path}: no pelvis (or hips) in the recording")
    return Recording(t, joints, positions, confidence)


# ------------------------------------------------------------------ CSV sources
def _csv(path: Path) -> tuple[list[str], np.ndarray]:
    """The header (lower case) and the numbers of a CSV file (empty cells: NaN)."""
    rows = csv_rows(path, "CSV")
    if len(rows) < 2:
        raise SkeletonRecordingError(f"{path}: no frames")
    header = [h.strip().lower() for h in rows[0]]
    values = np.full((len(rows) - 1, len(header)), np.nan)
    for i, row in enumerate(rows[1:]):
        if len(row) != len(header):
            raise SkeletonRecordingError(
                f"{path}:{i + 2}: {len(row)} cells, the header has {len(header)}"
            )
        for j, cell in enumerate(row):
            if cell.strip() and cell.strip().lower() != "nan":
                try:
                    values[i, j] = float(cell)
                except ValueError:
                    raise SkeletonRecordingError(
                        f"{path}:{i + 2}: {header[j]} {cell!r} is not a number"
                    ) from None
    return header, values


def _times(path: Path, header: list[str], values: np.ndarray, fps: float | None) -> np.ndarray:
    """Seconds of each row: its ``time`` column, else ``frame`` (or the row) / ``fps``."""
    if "time" in header:
        t = values[:, header.index("time")]
    elif fps is None:
        raise SkeletonRecordingError(f"{path}: no time column: give --fps")
    else:
        frames = values[:, header.index("frame")] if "frame" in header else np.arange(len(values))
        t = frames / fps
    if np.isnan(t).any() or (np.diff(t) <= 0).any():
        raise SkeletonRecordingError(f"{path}: the frames' times must be given and increase")
    return t - t[0]


def _column(path: Path, header: list[str], name: str) -> int:
    if name not in header:
        raise SkeletonRecordingError(f"{path}: no column {name!r}")
    return header.index(name)


def _mediapipe33(path: Path, fps: float | None):
    header, values = _csv(path)

    def landmark(n: int) -> np.ndarray:
        return values[:, [_column(path, header, f"p{n}_{k}") for k in "xyz"]]

    joints = [j for j in JOINTS if j in MEDIAPIPE or j == "spine"]
    positions = {j: np.mean([landmark(n) for n in MEDIAPIPE[j]], axis=0) for j in MEDIAPIPE}
    positions["spine"] = (positions["pelvis"] + positions["neck"]) / 2
    stacked = np.stack([positions[j] for j in joints], axis=1)
    return _times(path, header, values, fps), tuple(joints), stacked, np.ones(stacked.shape[:2])


def _kinect25(path: Path, fps: float | None):
    header, values = _csv(path)
    joints = tuple(JOINTS)
    positions = np.stack(
        [values[:, [_column(path, header, f"{KINECT[j]}_{k}") for k in "xyz"]] for j in joints],
        axis=1,
    )
    confidence = np.ones(positions.shape[:2])
    for i, j in enumerate(joints):
        if f"{KINECT[j]}_state" in header:
            state = values[:, header.index(f"{KINECT[j]}_state")]
            confidence[:, i] = np.select([state >= 2, state >= 1], [1.0, 0.5], 0.0)
            positions[state < 1, i] = np.nan
    return _times(path, header, values, fps), joints, positions, confidence


# ------------------------------------------------------------------ BVH
def _bvh(path: Path, fps: float | None):
    import bvhio  # only an import of BVH needs it

    try:
        bvh = bvhio.readAsBvh(str(path))
        root = bvhio.convertBvhToHierarchy(bvh.Root)
    except OSError as e:
        raise SkeletonRecordingError(f"{path}: cannot read: {e.strerror}") from None
    except Exception as e:  # the library raises what it meets: say which file and why
        raise SkeletonRecordingError(f"{path}: not a BVH file bvhio can read ({e})") from None
    # "mixamorig:LeftUpLeg" and "LeftUpLeg" alike
    named = {joint.Name.lower().split(":")[-1]: joint for joint, _, _ in root.layout()}
    found = {}
    for ours, aliases in BVH.items():
        match = next((named[a] for a in aliases if a in named), None)
        if match is not None:
            found[ours] = match
    joints = tuple(j for j in JOINTS if j in found)
    frames, frame_time = int(bvh.FrameCount), float(bvh.FrameTime)
    if frames == 0 or not joints:
        raise SkeletonRecordingError(f"{path}: no frames, or none of our joints")
    positions = np.empty((frames, len(joints), 3))
    for f in range(frames):
        root.loadPose(f)
        positions[f] = [tuple(found[j].PositionWorld) for j in joints]
    step = 1.0 / fps if fps else frame_time
    return np.arange(frames) * step, joints, positions, np.ones(positions.shape[:2])


READERS: dict[str, Callable] = {"mediapipe33": _mediapipe33, "bvh": _bvh, "kinect25": _kinect25}
