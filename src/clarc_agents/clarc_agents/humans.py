"""The patient as the ROS for HRI tools see it (REP-155), pure: ids, topic names, frames and the
body's 2D skeleton. The ROS side is ``nodes/humans_topics.py``.

REP-155 splits a human into parts seen for a while (a body, a voice) and a person they belong
to. Ids are short random lowercase names, valid inside a topic name; a body's id lives while the
tracker keeps it: a body lost and found again is a new body. CLARC has no face recognition,
so its person is anonymous: a new person id with each new body or face.
"""

from __future__ import annotations

import math
import random
import string
from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

from clarc_agents.gug.skeleton import JOINTS

ID_LENGTH = 5  # letters, as ROS4HRI's trackers make them
# REP-155's voice id for a microphone that cannot tell speakers apart
ANONYMOUS_SPEAKER = "anonymous_speaker"
LOCALE = "en_US"  # of what the patient says (the recogniser's language)

BODIES_TRACKED = "/humans/bodies/tracked"
PERSONS_TRACKED = "/humans/persons/tracked"
VOICES_TRACKED = "/humans/voices/tracked"


def body_topic(body_id: str, leaf: str) -> str:
    return f"/humans/bodies/{body_id}/{leaf}"


def person_topic(person_id: str, leaf: str) -> str:
    return f"/humans/persons/{person_id}/{leaf}"


def voice_topic(voice_id: str, leaf: str) -> str:
    return f"/humans/voices/{voice_id}/{leaf}"


def body_frame(body_id: str) -> str:
    return f"body_{body_id}"


def person_frame(person_id: str) -> str:
    return f"person_{person_id}"


# never an id: person_<id> would be the DSR's frame of that joint (gug/skeleton.py's joint_node)
RESERVED = frozenset(JOINTS)


def new_id(rng: random.Random) -> str:
    while True:
        made = "".join(rng.choice(string.ascii_lowercase) for _ in range(ID_LENGTH))
        if made not in RESERVED:
            return made


class TrackedPart:
    """One part's id: made when it is first seen, dropped when it is lost."""

    def __init__(self, rng: random.Random):
        self._rng = rng
        self.id: str | None = None

    def seen(self) -> tuple[str, bool]:
        """(the id, whether it is new)."""
        if self.id is not None:
            return self.id, False
        self.id = new_id(self._rng)
        return self.id, True

    def lost(self) -> str | None:
        """The id that ended, if there was one."""
        gone, self.id = self.id, None
        return gone


class Absence:
    """How long a tracker has gone without the patient: frames, and seconds by the frames' own
    capture stamps (a busy reader may take a second's frames at once)."""

    def __init__(self):
        self.frames = 0
        self.since = 0.0  # the stamp of the first frame without the patient

    def present(self) -> None:
        self.frames = 0

    def absent(self, stamp: float) -> None:
        if self.frames == 0:
            self.since = stamp
        self.frames += 1

    def lost(self, stamp: float, frames: int, seconds: float) -> bool:
        """Gone for at least ``frames`` frames and ``seconds`` s (a tracker loses a body for a
        moment now and then: one dropped frame is not a person leaving)."""
        return self.frames >= frames and stamp - self.since >= seconds


# OpenPose's COCO keypoints, Skeleton2D's order, and the Kinect joint (gug/skeleton.py's JOINTS)
# at each: a Kinect has no nose, eyes, ears, elbows or wrists in CLARC's frames (confidence 0)
COCO18 = (
    ("nose", None),
    ("neck", "neck"),
    ("right_shoulder", "shoulder_right"),
    ("right_elbow", None),
    ("right_wrist", None),
    ("left_shoulder", "shoulder_left"),
    ("left_elbow", None),
    ("left_wrist", None),
    ("right_hip", "hip_right"),
    ("right_knee", "knee_right"),
    ("right_ankle", "ankle_right"),
    ("left_hip", "hip_left"),
    ("left_knee", "knee_left"),
    ("left_ankle", "ankle_left"),
    ("left_eye", None),
    ("right_eye", None),
    ("left_ear", None),
    ("right_ear", None),
)


@dataclass(frozen=True)
class Pinhole:
    """The Kinect's colour camera, at the Kinect's origin looking along its x axis (REP-103:
    x forward, y left, z up): ``focal`` pixels at ``width`` x ``height``."""

    width: int
    height: int
    focal: float

    def normalised(self, p: np.ndarray) -> tuple[float, float] | None:
        """Where the point ``p`` (m, Kinect's frame) is in the image, from its top-left corner
        as fractions of its width and height; None when it is behind the camera or off the
        image."""
        x, y, z = (float(v) for v in p)
        if x <= 0.0:
            return None
        u = (self.width / 2 - self.focal * y / x) / self.width
        v = (self.height / 2 - self.focal * z / x) / self.height
        return (u, v) if 0.0 <= u <= 1.0 and 0.0 <= v <= 1.0 else None


def skeleton2d(
    joints: Mapping[str, tuple[np.ndarray, float]], camera: Pinhole
) -> list[tuple[float, float, float]]:
    """The 18 keypoints (x, y, confidence) of Skeleton2D from a frame's joints (m, Kinect's frame;
    ``gug.skeleton.parse_skeleton``); a keypoint the Kinect lacks or does not see: (0, 0, 0)."""
    out = []
    for _, joint in COCO18:
        seen = joints.get(joint) if joint is not None else None
        at = camera.normalised(seen[0]) if seen is not None else None
        out.append((at[0], at[1], seen[1]) if at is not None else (0.0, 0.0, 0.0))
    return out


def body_pose(
    joints: Mapping[str, tuple[np.ndarray, float]], yaw: float
) -> tuple[tuple[float, float, float], tuple[float, float, float, float]]:
    """``body_<id>`` in the Kinect's frame: at the pelvis, x where the body faces (``yaw``), z up
    (translation in m, quaternion x, y, z, w)."""
    pelvis = joints["pelvis"][0]
    return (
        (float(pelvis[0]), float(pelvis[1]), float(pelvis[2])),
        (0.0, 0.0, math.sin(yaw / 2), math.cos(yaw / 2)),
    )
