"""A Kinect skeleton frame as one DSR transaction (pure): the person's pose (the pelvis, turned
as the body faces) under the Kinect, and each joint as a geometric child of the person, so a
joint anywhere in the room is one kinematic chain away (``Graph.transform``). The joints'
confidences go on the person as one vector, the frame's time as ``frame_time``, and every frame
of the transaction as it came from the sensor in ``skeleton_frames`` (one row each).

Node names: ``person_<joint>`` (``person_pelvis``, ``person_knee_left``), type ``joint``.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import Any

import numpy as np

from dsr_graph.model.graph import Graph

JOINTS = (
    "head",
    "neck",
    "spine",
    "pelvis",
    "shoulder_left",
    "shoulder_right",
    "hip_left",
    "hip_right",
    "knee_left",
    "knee_right",
    "ankle_left",
    "ankle_right",
    "foot_left",
    "foot_right",
)
SIDES = (("hip_left", "hip_right"), ("shoulder_left", "shoulder_right"))
MM = 1000.0
SENSOR = "kinect"  # the DSR node (and tf frame) whose frame the Kinect's joints are given in


def joint_node(joint: str) -> str:
    return f"person_{joint}"


def parse_skeleton(raw: Any) -> dict[str, tuple[np.ndarray, float]]:
    """{joint: (position in m, confidence)} from a frame's "skeleton" (mm); ValueError naming
    what is wrong. Unknown joints are an error; missing ones are allowed (not tracked)."""
    if not isinstance(raw, Mapping):
        raise ValueError(f"skeleton must map joints to {{p, c}}, got {type(raw).__name__}")
    out = {}
    for joint, value in raw.items():
        if joint not in JOINTS:
            raise ValueError(f"unknown joint {joint!r}; the joints are {', '.join(JOINTS)}")
        p = value.get("p") if isinstance(value, Mapping) else None
        c = value.get("c", 1.0) if isinstance(value, Mapping) else None
        if (
            not isinstance(p, list)
            or len(p) != 3
            or not all(isinstance(v, (int, float)) and math.isfinite(v) for v in p)
        ):
            raise ValueError(f"{joint}: p must be 3 finite numbers (mm), got {p!r}")
        if isinstance(c, bool) or not isinstance(c, (int, float)) or not 0.0 <= c <= 1.0:
            raise ValueError(f"{joint}: c must be a confidence from 0 to 1, got {c!r}")
        out[joint] = (np.array(p, dtype=float) / MM, float(c))
    if "pelvis" not in out:
        raise ValueError("a skeleton without its pelvis cannot be placed")
    return out


def heading(joints: Mapping[str, tuple[np.ndarray, float]]) -> float:
    """Where the body faces (yaw about the vertical, rad) from its hips and shoulders."""
    lefts = [joints[a][0] - joints[b][0] for a, b in SIDES if a in joints and b in joints]
    if not lefts:
        return 0.0
    left = np.mean(lefts, axis=0)
    return math.atan2(-left[0], left[1])


def skeleton_tx(
    graph: Graph, joints: Mapping[str, tuple[np.ndarray, float]], stamp: float
) -> dict[str, Any]:
    """The transaction writing one frame (``frames_tx`` of one)."""
    return frames_tx(graph, [(joints, stamp)])


def frames_tx(
    graph: Graph, frames: list[tuple[Mapping[str, tuple[np.ndarray, float]], float]]
) -> dict[str, Any]:
    """One transaction writing every frame Person took since its last one, in their order: the
    geometry (the person under the Kinect, the joints under the person) of the newest, and all
    of them, as the sensor gave them, in the person's ``skeleton_frames`` (``frame_row``), so a
    reader of the delta (the gait analyser, ``frames_in``) sees each one however many frames a
    transaction carries: a busy machine writes more of them at a time, never fewer."""
    joints, stamp = frames[-1]
    known = {joint for joint in JOINTS if graph.find(joint_node(joint)) is not None}
    person, *under = _geometry_ops(joints, known)
    attrs = {
        "frame_time": stamp,
        "joint_confidence": [joints[j][1] if j in joints else 0.0 for j in JOINTS],
        "skeleton_frames": [frame_row(j, t) for j, t in frames],
    }
    return {"ops": [person, {"op": "set_node_attrs", "node": "person", "attrs": attrs}, *under]}


def frame_row(joints: Mapping[str, tuple[np.ndarray, float]], stamp: float) -> list[float]:
    """A frame as one row of ``skeleton_frames``: its capture time (epoch s), then x, y, z (m,
    in the Kinect's frame) and confidence of each joint in ``JOINTS`` order (0, 0, 0, 0: not
    tracked)."""
    row = [float(stamp)]
    for joint in JOINTS:
        if joint in joints:
            p, c = joints[joint]
            row += [round(float(v), 4) for v in p] + [round(float(c), 3)]
        else:
            row += [0.0, 0.0, 0.0, 0.0]
    return row


ROW = 1 + 4 * len(JOINTS)


def rows_to_frames(rows: Any) -> list[tuple[float, dict[str, tuple[np.ndarray, float]]]]:
    """``skeleton_frames`` read back: (capture time, {joint: (position in the Kinect's frame,
    confidence)}) per row, untracked joints left out; rows of another shape are skipped."""
    out = []
    for row in rows or ():
        if not isinstance(row, list) or len(row) != ROW:
            continue
        values = np.asarray(row[1:], dtype=float).reshape(len(JOINTS), 4)
        joints = {
            joint: (values[i, :3], float(values[i, 3]))
            for i, joint in enumerate(JOINTS)
            if values[i, 3] > 0.0
        }
        out.append((float(row[0]), joints))
    return out


def _geometry_ops(
    joints: Mapping[str, tuple[np.ndarray, float]], known: set[str]
) -> list[dict[str, Any]]:
    """A frame's geometry; ``known``: the joints whose nodes exist already."""
    pelvis = joints["pelvis"][0]
    yaw = heading(joints)
    c, s = math.cos(-yaw), math.sin(-yaw)
    ops: list[dict[str, Any]] = [
        {
            "op": "set_rt",
            "from": SENSOR,
            "to": "person",
            "rt": {"translation": pelvis.round(4).tolist(), "rotation_euler_xyz": [0.0, 0.0, yaw]},
        },
    ]
    for joint, (p, _) in joints.items():
        d = p - pelvis  # in the person's frame: turned back by the body's yaw
        local = [round(c * d[0] - s * d[1], 4), round(s * d[0] + c * d[1], 4), round(d[2], 4)]
        rt = {"translation": local, "rotation_euler_xyz": [0.0, 0.0, 0.0]}
        name = joint_node(joint)
        if joint not in known:
            ops.append({"op": "insert_node", "name": name, "type": "joint"})
            ops.append({"op": "insert_edge", "from": "person", "to": name, "type": "RT", "rt": rt})
        else:
            ops.append({"op": "set_rt", "from": "person", "to": name, "rt": rt})
    return ops


def frames_in(
    delta: Mapping[str, Any],
) -> list[tuple[float, dict[str, tuple[np.ndarray, float]]]]:
    """The skeleton frames a delta wrote, in order (``rows_to_frames`` of each
    ``skeleton_frames`` written on the person)."""
    found = []
    for op in delta.get("ops", ()):
        if op.get("op") == "set_node_attrs" and op.get("node") == "person":
            found += rows_to_frames((op.get("attrs") or {}).get("skeleton_frames"))
    return found


def frames_on(graph: Graph) -> list[tuple[float, dict[str, tuple[np.ndarray, float]]]]:
    """The frames of the person's last write, as the graph holds them (after a resync)."""
    person = graph.find("person")
    return [] if person is None else rows_to_frames(person.attrs.get("skeleton_frames"))


def latest_frame_time(graph: Graph) -> float | None:
    """The capture stamp (epoch s) of the newest frame Person wrote; None: no frame yet."""
    person = graph.find("person")
    stamp = None if person is None else person.attrs.get("frame_time")
    return float(stamp) if isinstance(stamp, int | float) else None
