"""The patient as REP-155 has a human (clarc_agents/humans.py): ids valid in topic names that
live while the part is tracked, absence judged by frames and capture stamps, the body's frame at
the pelvis facing where the body faces, and its 2D skeleton in the Kinect's colour image in
Skeleton2D's (OpenPose COCO) order."""

import math
import random
import re

import numpy as np
import pytest

from clarc_agents.gug.skeleton import heading, parse_skeleton
from clarc_agents.humans import (
    COCO18,
    Absence,
    Pinhole,
    TrackedPart,
    body_pose,
    body_topic,
    person_frame,
    skeleton2d,
)

CAMERA = Pinhole(640, 480, 525.0)


def standing(at_x_mm=2000.0, facing_kinect=True):
    """A standing body ``at_x_mm`` in front of the Kinect (x forward, y left, z up, mm)."""
    side = -1.0 if facing_kinect else 1.0  # its left is the Kinect's right when facing it
    raw = {
        "pelvis": [0.0, 0.0, 0.0],
        "neck": [0.0, 0.0, 500.0],
        "head": [0.0, 0.0, 650.0],
        "shoulder_left": [0.0, side * 180.0, 450.0],
        "shoulder_right": [0.0, -side * 180.0, 450.0],
        "hip_left": [0.0, side * 100.0, 0.0],
        "hip_right": [0.0, -side * 100.0, 0.0],
        "knee_left": [0.0, side * 100.0, -450.0],
        "knee_right": [0.0, -side * 100.0, -450.0],
        "ankle_left": [0.0, side * 100.0, -850.0],
        "ankle_right": [0.0, -side * 100.0, -850.0],
    }
    return parse_skeleton(
        {j: {"p": [at_x_mm + p[0], p[1], p[2]], "c": 0.9} for j, p in raw.items()}
    )


def test_an_id_lives_while_its_part_is_tracked_and_is_a_topic_name_part():
    part = TrackedPart(random.Random(3))
    first, new = part.seen()
    assert new and re.fullmatch(r"[a-z]{5}", first)
    assert part.seen() == (first, False)
    assert part.lost() == first and part.id is None and part.lost() is None
    second, new = part.seen()
    assert new and second != first  # lost and found again: another body
    assert body_topic(second, "skeleton2d") == f"/humans/bodies/{second}/skeleton2d"
    assert person_frame(second) == f"person_{second}"


def test_an_id_is_never_a_joint_s_name():
    class Rigged(random.Random):  # spells "spine", then "abcde"
        letters = iter("spineabcde")

        def choice(self, seq):
            return next(self.letters)

    assert TrackedPart(Rigged()).seen() == ("abcde", True)


def test_a_part_is_lost_after_enough_frames_and_seconds_by_the_frames_stamps():
    absence = Absence()
    absence.absent(100.0)
    absence.absent(100.1)
    assert not absence.lost(100.1, frames=3, seconds=0.5)  # too few frames, too short
    absence.absent(100.2)
    assert not absence.lost(100.2, frames=3, seconds=0.5)  # enough frames, too short
    assert absence.lost(100.6, frames=3, seconds=0.5)
    absence.present()
    absence.absent(200.0)
    assert absence.since == 200.0 and absence.frames == 1


def test_the_body_frame_is_at_the_pelvis_facing_where_the_body_faces():
    joints = standing(facing_kinect=True)
    yaw = heading(joints)
    assert math.isclose(abs(yaw), math.pi, abs_tol=1e-9)  # it faces back at the Kinect
    translation, (qx, qy, qz, qw) = body_pose(joints, yaw)
    assert translation == pytest.approx((2.0, 0.0, 0.0))
    assert (qx, qy) == (0.0, 0.0) and math.isclose(qx**2 + qy**2 + qz**2 + qw**2, 1.0)
    assert math.isclose(2 * math.atan2(qz, qw) % (2 * math.pi), yaw % (2 * math.pi))
    _, away = body_pose(standing(facing_kinect=False), heading(standing(facing_kinect=False)))
    assert away == pytest.approx((0.0, 0.0, 0.0, 1.0))  # facing along the Kinect's x


def test_the_2d_skeleton_follows_coco_order_and_the_image_s_axes():
    points = skeleton2d(standing(facing_kinect=True), CAMERA)
    assert len(points) == 18 == len(COCO18)
    by_name = {name: p for (name, _), p in zip(COCO18, points, strict=True)}
    # the Kinect has no nose, eyes, ears, elbows or wrists in CLARC's frames
    for missing in ("nose", "left_eye", "right_ear", "left_elbow", "right_wrist"):
        assert by_name[missing] == (0.0, 0.0, 0.0)
    # facing the camera, the body's right is on the image's left; up is towards row 0
    assert by_name["right_shoulder"][0] < by_name["neck"][0] < by_name["left_shoulder"][0]
    assert by_name["neck"][1] < by_name["right_hip"][1] < by_name["right_ankle"][1]
    assert by_name["neck"][0] == pytest.approx(0.5) and by_name["neck"][2] == pytest.approx(0.9)
    # 0.18 m to the Kinect's right at 2 m, f = 525 px: 47.25 px right of the image's centre
    assert by_name["left_shoulder"][0] == pytest.approx(0.5 + 525 * 0.18 / 2.0 / 640)


def test_a_point_behind_the_camera_or_off_the_image_is_not_seen():
    assert CAMERA.normalised(np.array([-1.0, 0.0, 0.0])) is None
    assert CAMERA.normalised(np.array([0.0, 0.0, 0.0])) is None
    assert CAMERA.normalised(np.array([0.5, 0.0, 1.0])) is None  # far above the image's top
    assert CAMERA.normalised(np.array([1.0, 0.0, 0.0])) == (0.5, 0.5)
    close = skeleton2d(standing(at_x_mm=300.0), CAMERA)
    assert close[COCO18.index(("right_ankle", "ankle_right"))] == (0.0, 0.0, 0.0)
