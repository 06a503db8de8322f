"""Recorded movement for the Get Up & Go: CLARC's skeleton-recording file, the importers
(MediaPipe Pose 33, BVH, Kinect v2's 25 joints), placing a recording at the trial's chair, a
scenario's ``recording:`` and the Kinect stand-in's frames from it, timed as the DSR's analyser
times them."""

import math
import random
from pathlib import Path

import numpy as np
import pytest
from gug_checks import F77_READ, F77_TOTAL, boundaries_as_read

from clarc_agents.exceptions import ScenarioError
from clarc_agents.gug.phases import sample, time_trial
from clarc_agents.gug.skeleton import parse_skeleton
from clarc_sim.console.clarc_cli import main as clarc
from clarc_sim.devices.skeleton_frames import KinectModel, TrialPlace, recorded
from clarc_sim.exceptions import SkeletonRecordingError
from clarc_sim.patient.gait_motion import SEATED_X
from clarc_sim.patient.scenario import load
from clarc_sim.patient.skeleton_import import import_recording
from clarc_sim.patient.skeleton_recording import Recording, placed, read, write

PLACE = TrialPlace(4500.0, 0.0, -1200.0, math.pi)  # the CLARC room's gug_chair, seen by the Kinect
BVH = """HIERARCHY
ROOT Hips
{
  OFFSET 0 0 0
  CHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation
  JOINT LeftUpLeg
  {
    OFFSET 10 0 0
    CHANNELS 3 Zrotation Xrotation Yrotation
    JOINT LeftLeg
    {
      OFFSET 0 -45 0
      CHANNELS 3 Zrotation Xrotation Yrotation
      JOINT LeftFoot
      {
        OFFSET 0 -40 0
        CHANNELS 3 Zrotation Xrotation Yrotation
        End Site
        {
          OFFSET 0 0 10
        }
      }
    }
  }
}
MOTION
Frames: 2
Frame Time: 0.04
0 90 0 0 0 0 0 0 0 0 0 0 0 0 0
10 90 0 0 0 90 90 0 0 0 0 0 0 0 0
"""


@pytest.fixture
def f77(motion_dir, tmp_path):
    """../shared's recorded Timed Up and Go, imported and written as CLARC's recording."""
    out = tmp_path / "f77.csv"
    assert (
        clarc(
            [
                "skeleton",
                "import",
                "--from",
                "mediapipe33",
                str(motion_dir / "tug_f77_mediapipe33.csv"),
                str(out),
            ]
        )
        == 0
    )
    return out


def test_an_imported_recording_reads_back_and_is_placed_at_the_chair(f77):
    recording = read(f77)
    assert len(recording.t) == 2615 and recording.duration == pytest.approx(2614 / 59.94)
    assert "pelvis" in recording.joints and "spine" in recording.joints
    feet = recording.positions[:, recording.joints.index("foot_left"), 2]
    assert np.percentile(feet, 2) == pytest.approx(0.0, abs=0.03)  # the floor at z = 0
    put = placed(recording)
    pelvis = put.joint("pelvis")
    seated = recording.t < 0.5
    assert np.mean(pelvis[seated], axis=0)[:2] == pytest.approx([SEATED_X, 0.0], abs=1e-6)
    far = pelvis[np.argmax(pelvis[:, 0])]
    assert far[0] > 3.0 and abs(far[1]) < 1e-6  # the first walk along +x
    assert put.positions[:, :, 2] == pytest.approx(recording.positions[:, :, 2])  # heights kept


def test_the_kinect_s_frames_of_a_recording_are_timed_as_the_recording_reads(f77):
    """The Kinect stand-in at 30 frames/s plays the placed recording into its frame (mm); the
    analyser's samples from them time it within 0.5 s of the hand reading."""
    put, samples = placed(read(f77)), []
    sensor = KinectModel(random.Random(1), noise_mm=10.0)  # a Kinect's noise on top
    c, s = math.cos(-PLACE.yaw), math.sin(-PLACE.yaw)
    for k in range(int(44 * 30)):
        raw, _ = sensor.see(recorded(put, k / 30, PLACE), k / 30)
        joints, trust = {}, {}
        for name, (p, confidence) in parse_skeleton(raw).items():
            x, y, z = p[0] - PLACE.x / 1000, p[1] - PLACE.y / 1000, p[2] - PLACE.z / 1000
            joints[name], trust[name] = (c * x - s * y, s * x + c * y, z), confidence
        samples.append(sample(k / 30, joints, trust))
    timed = time_trial(samples, 0.0)
    assert timed.tug_seconds == pytest.approx(F77_TOTAL, abs=0.5)
    boundaries_as_read(timed.moves, F77_READ)


def test_a_recording_s_frame_is_the_last_taken_and_a_frame_without_a_pelvis_is_none():
    t = np.array([0.0, 0.1, 0.2])
    positions = np.zeros((3, 2, 3))
    positions[:, 0, 0] = [0.0, 1.0, 2.0]
    confidence = np.array([[1.0, 1.0], [0.0, 1.0], [1.0, 0.5]])
    positions[1, 0] = np.nan
    r = Recording(t, ("pelvis", "head"), positions, confidence)
    assert [r.frame_at(x) for x in (-1.0, 0.0, 0.15, 0.2, 9.0)] == [0, 0, 1, 2, 2]
    assert recorded(r, 0.15, PLACE) is None  # no pelvis in frame 1
    frame = recorded(r, 0.2, PLACE)
    assert frame["head"]["c"] == 0.5 and frame["pelvis"]["p"] == pytest.approx(
        PLACE.to_kinect([2.0, 0.0, 0.0])
    )


def test_kinect25_and_bvh_are_imported_to_metres_z_up_and_the_floor(tmp_path):
    names = {
        "head": "Head", "neck": "SpineShoulder", "spine": "SpineMid", "pelvis": "SpineBase",
        "shoulder_left": "ShoulderLeft", "shoulder_right": "ShoulderRight",
        "hip_left": "HipLeft", "hip_right": "HipRight", "knee_left": "KneeLeft",
        "knee_right": "KneeRight", "ankle_left": "AnkleLeft", "ankle_right": "AnkleRight",
        "foot_left": "FootLeft", "foot_right": "FootRight",
    }  # fmt: skip
    heights = {"foot_left": -0.8, "foot_right": -0.8, "pelvis": 0.1}  # the camera 0.8 m up
    header = ["time"] + [f"{n}_{k}" for n in names.values() for k in ("X", "Y", "Z", "State")]
    rows = []
    for i, time in enumerate((10.0, 10.033)):
        row = [str(time)]
        for ours in names:
            state = 1 if ours == "head" else (0 if ours == "neck" and i == 1 else 2)
            row += ["0.1", str(heights.get(ours, 0.5)), str(2.0 + i), str(state)]
        rows.append(",".join(row))
    source = tmp_path / "k.csv"
    source.write_text(",".join(header) + "\n" + "\n".join(rows) + "\n")
    k = import_recording("kinect25", source)
    assert k.t == pytest.approx([0.0, 0.033])
    pelvis = k.joint("pelvis")
    assert pelvis[0] == pytest.approx([0.1, -2.0, 0.9])  # y up became z up; floor at 0
    head = k.joints.index("head")
    assert k.confidence[0, head] == 0.5  # inferred
    assert np.isnan(k.positions[1, k.joints.index("neck")]).all()  # not tracked
    bvh = tmp_path / "walk.bvh"
    bvh.write_text(BVH)
    b = import_recording("bvh", bvh)
    assert b.joints == ("pelvis", "hip_left", "knee_left", "ankle_left")
    assert b.t == pytest.approx([0.0, 0.04])
    # frame 1: the body turned 90 degrees about the vertical, the thigh swung forward
    assert b.joint("knee_left")[1] - b.joint("pelvis")[1] == pytest.approx([0, 0.55, 0], abs=1e-6)
    assert b.joint("ankle_left")[0][2] == pytest.approx(0.0, abs=0.02)  # the foot on the floor


@pytest.mark.parametrize(
    "content, error",
    [
        ("t,pelvis_x\n", ":1: a skeleton recording starts with"),
        ("# clarc-skeleton 1\nt,tail_x,tail_y,tail_z,tail_c\n0,0,0,0,1\n", "unknown joint 'tail'"),
        ("# clarc-skeleton 1\nt,head_x,head_y,head_z,head_c\n0,0,0,0,1\n", "without the pelvis"),
        (
            "# clarc-skeleton 1\nt,pelvis_x,pelvis_y,pelvis_z,pelvis_c\n0,0,0,0,1\n0,0,0,0,1\n",
            ":4: t 0.0 does not come after 0.0",
        ),
        (
            "# clarc-skeleton 1\nt,pelvis_x,pelvis_y,pelvis_z,pelvis_c\n0,0,x,0,1\n",
            ":3: pelvis_y 'x' is not a number",
        ),
        (
            "# clarc-skeleton 1\nt,pelvis_x,pelvis_y,pelvis_z,pelvis_c\n0,0,0,0,2\n",
            ":3: pelvis_c 2.0 is not a confidence",
        ),
        (
            "# clarc-skeleton 1\nt,pelvis_x,pelvis_y,pelvis_z,pelvis_c\n0,0,,0,1\n",
            ":3: pelvis has some of x, y, z, c empty",
        ),
    ],
)
def test_a_bad_recording_is_refused_naming_the_line(tmp_path, content, error):
    path = tmp_path / "bad.csv"
    path.write_text(content)
    with pytest.raises(SkeletonRecordingError, match=error):
        read(path)


def test_a_bad_import_is_refused_by_name(tmp_path, capsys):
    with pytest.raises(SkeletonRecordingError, match="unknown format 'c3d'"):
        import_recording("c3d", tmp_path / "x")
    source = tmp_path / "m.csv"
    source.write_text("frame,p1_x,p1_y,p1_z\n0,1,2,3\n")
    with pytest.raises(SkeletonRecordingError, match="no column 'p8_x'"):
        import_recording("mediapipe33", source)
    with pytest.raises(SkeletonRecordingError, match="--up must be one of"):
        import_recording("mediapipe33", source, up="w")
    assert clarc(["skeleton", "import", "--from", "bvh", str(tmp_path / "none.bvh"), "o"]) == 1
    assert "clarc skeleton:" in capsys.readouterr().err


def write_scenario(folder: Path, body: str) -> Path:
    path = folder / "rec.yaml"
    path.write_text("test: get_up_and_go\npatient: Rosa\n" + body)
    return path


def test_a_scenario_plays_a_recording_named_beside_it(f77, tmp_path):
    folder = tmp_path / "scenarios"
    folder.mkdir()
    (folder / "tug.csv").write_bytes(f77.read_bytes())
    s = load(str(write_scenario(folder, "recording: tug.csv\noffset: 0.5\n")))
    assert s.recording == str(folder / "tug.csv") and s.offset == 0.5 and s.motion is None
    for body, error in [
        ("recording: none.csv\n", r"rec.yaml:3: recording: .*none.csv: cannot read"),
        ("recording: tug.csv\noffset: 50\n", "rec.yaml:4: offset 50 s is past the recording"),
        ("recording: tug.csv\nmotion: {}\n", 'rec.yaml:4: a scenario has "motion" or "recording"'),
        ("motion: {reaction: 1, rise: 1, walk_out: 1, turn: 1, walk_back: 1, sit: 1}\noffset: 1\n",
         'rec.yaml:4: "offset" goes with a "recording"'),
    ]:  # fmt: skip
        with pytest.raises(ScenarioError, match=error):
            load(str(write_scenario(folder, body)))


def test_a_recording_with_no_walk_cannot_be_placed(tmp_path):
    t = np.arange(10) * 0.1
    still = Recording(t, ("pelvis",), np.zeros((10, 1, 3)), np.ones((10, 1)))
    with pytest.raises(SkeletonRecordingError, match="never goes 1 m"):
        placed(still)
    write(still, tmp_path / "still.csv")
    assert read(tmp_path / "still.csv").positions == pytest.approx(still.positions)
