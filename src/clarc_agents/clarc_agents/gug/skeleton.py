"""A Kinect skeleton frame as one DSR transaction (pure): the person's pose (the pelvis, turned
as the body faces) under the Kinect, and each joint as a geometric child of the person, so a
joint anywhere in the room is one kinematic chain away (``Graph.transform``). The joints'
confidences go on the person as one vector, and the frame's time as ``frame_time``.

Node names: ``person_<joint>`` (``person_pelvis``, ``person_knee_left``), type ``joint``.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import Any

import numpy as np

from dsr_graph.model import rigid
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
    graph: Graph,
    joints: Mapping[str, tuple[np.ndarray, float]],
    stamp: float,
    sensor_gap: float | None = None,
) -> dict[str, Any]:
    """The transaction writing one frame: person pose under the Kinect, joints under it.
    ``sensor_gap``: the longest time between two frames the sensor gave since the frame written
    before (Person skips frames when the DSR is slower than the Kinect; a reader must not take
    that for the sensor losing the person)."""
    tx = frames_tx(graph, [(joints, stamp)])
    if sensor_gap is not None:
        tx["ops"][1]["attrs"]["sensor_gap"] = round(float(sensor_gap), 4)
    return tx


def frames_tx(
    graph: Graph, frames: list[tuple[Mapping[str, tuple[np.ndarray, float]], float]]
) -> dict[str, Any]:
    """One transaction writing several frames in their order (Person, when the DSR is slower
    than the Kinect): each frame's ops in turn, so the graph ends at the last frame and a reader
    of the delta (the gait analyser, ``frames_in``) sees every one of them."""
    ops: list[dict[str, Any]] = []
    known = {joint for joint in JOINTS if graph.find(joint_node(joint)) is not None}
    for joints, stamp in frames:
        ops += _frame_ops(joints, stamp, known)
        known |= set(joints)
    return {"ops": ops}


def _frame_ops(
    joints: Mapping[str, tuple[np.ndarray, float]], stamp: float, known: set[str]
) -> list[dict[str, Any]]:
    """One frame's ops; ``known``: the joints whose nodes exist already."""
    pelvis = joints["pelvis"][0]
    yaw = heading(joints)
    c, s = math.cos(-yaw), math.sin(-yaw)
    ops: list[dict[str, Any]] = [
        {
            "op": "set_rt",
            "from": "kinect",
            "to": "person",
            "rt": {"translation": pelvis.round(4).tolist(), "rotation_euler_xyz": [0.0, 0.0, yaw]},
        },
        {
            "op": "set_node_attrs",
            "node": "person",
            "attrs": {
                "frame_time": stamp,
                "joint_confidence": [joints[j][1] if j in joints else 0.0 for j in JOINTS],
            },
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


def frames_in(delta: Mapping[str, Any]) -> list[tuple[float, np.ndarray, dict[str, np.ndarray]]]:
    """The skeleton frames a delta wrote, in order: (frame time, the person's pose under the
    Kinect, {joint: its pose under the person}) as 4x4 matrices; a frame starts at the person's
    ``set_rt`` (``frames_tx``'s order). The frame's ``sensor_gap``, when written, is under the
    joint key ``"sensor_gap"`` as a number."""
    found: list[tuple[float | None, np.ndarray, dict[str, Any]]] = []
    for op in delta.get("ops", ()):
        kind = op.get("op")
        if kind == "set_rt" and op.get("from") == "kinect" and op.get("to") == "person":
            found.append((None, rigid.from_json(op["rt"]), {}))
        elif not found:
            continue
        elif kind == "set_node_attrs" and op.get("node") == "person":
            attrs = op.get("attrs") or {}
            if attrs.get("frame_time") is not None:
                found[-1] = (float(attrs["frame_time"]), found[-1][1], found[-1][2])
            if attrs.get("sensor_gap") is not None:
                found[-1][2]["sensor_gap"] = float(attrs["sensor_gap"])
        elif kind in ("set_rt", "insert_edge") and op.get("from") == "person":
            name = str(op.get("to", ""))
            if name.startswith("person_") and op.get("type", "RT") == "RT" and "rt" in op:
                found[-1][2][name[len("person_") :]] = rigid.from_json(op["rt"])
    return [(t, person, joints) for t, person, joints in found if t is not None]
