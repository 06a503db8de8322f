"""Whether the person sits, stands or walks, from their skeleton's geometry (pure): the pelvis's
height above the floor and its speed over the floor. Person signals a change as the percept
``posture``, which its grammar's rule writes on the person node (grammars/person.yaml)."""

from __future__ import annotations

import math
from collections import deque

import numpy as np

from clarc_agents.gug.skeleton import SENSOR
from dsr_graph.model.graph import Graph

SITTING_BELOW = 0.70  # m: a seated pelvis is about 0.47 m up, a standing one about 0.95 m
WALKING_ABOVE = 0.30  # m/s of the patient's time over the floor
SPEED_OVER = 0.5  # s of the patient's time the speed is measured over
STEADY = 0.3  # s of the patient's time a new posture must hold before it is told (a sensor's
# slow noise must not flicker it)


def pelvis_in_room(graph: Graph, joints) -> np.ndarray:
    """The pelvis of a parsed skeleton frame (in the Kinect's frame) in the room's, z up from the
    floor: the kinematic chain room -> kinect of the DSR."""
    room_from_kinect = graph.transform("room", SENSOR)
    return room_from_kinect[:3, :3] @ joints["pelvis"][0] + room_from_kinect[:3, 3]


class PostureTracker:
    def __init__(self, scale: float = 1.0):
        self.scale = scale or 1.0
        self.posture = ""
        self._recent: deque[tuple[float, float, float]] = deque()  # (t, x, y)
        self._candidate, self._since = "", 0.0

    def update(self, stamp: float, pelvis_in_room) -> str | None:
        """The new posture when it changed (held for ``STEADY`` s), else None.
        ``stamp``: the frame's epoch seconds; ``pelvis_in_room``: x, y, z (m, z up from the
        floor)."""
        t = stamp / self.scale
        x, y, z = (float(v) for v in pelvis_in_room)
        self._recent.append((t, x, y))
        while self._recent and t - self._recent[0][0] > SPEED_OVER:
            self._recent.popleft()
        t0, x0, y0 = self._recent[0]
        speed = math.hypot(x - x0, y - y0) / (t - t0) if t > t0 else 0.0
        if z < SITTING_BELOW:
            now = "sitting"
        else:
            now = "walking" if speed > WALKING_ABOVE else "standing"
        if now != self._candidate:
            self._candidate, self._since = now, t
        if t - self._since >= STEADY and now != self.posture:
            self.posture = now
            return now
        return None
