"""The Get Up & Go timed from real human movement: ../shared/data/motion's recorded Timed Up
and Go (a 77-year-old woman, MediaPipe Pose 3D at 59.94 frames/s, with pauses: see its
SOURCE.md), through the same timing as the DSR's (``gug/phases.py``).

The times read from the data by hand (pelvis height, its position along the walkway, the
heading of the hips and shoulders, frame by frame), "go" at its first frame:
the hips leave the seat at 1.07 s and stop rising at 2.2 s; she stands until 4.1 s; walks out
until 13.3 s (3.9 m); stands still until 21.2 s; turns until 24.4 s; stands until 26.0 s;
walks back until 35.6 s; turns round to the chair from 35.7 s and is seated again at 40.5 s."""

import math

import numpy as np
import pytest
from gug_checks import F77_READ as READ
from gug_checks import F77_TOTAL, boundaries_as_read

from clarc_agents.gug.phases import sample, time_trial

# MediaPipe Pose landmark N is column pN+1 (SOURCE.md)
LANDMARKS = {"hip_left": 24, "hip_right": 25, "shoulder_left": 12, "shoulder_right": 13}


def samples_of(path):
    """The recording's frames as samples in the chair's frame, placed as the room has it: the
    walkway runs along the recording's +y (z up), the seated pelvis (its first half second) is
    0.15 m behind the chair's front, on its middle line."""
    data = np.genfromtxt(path, delimiter=",", names=True)
    t = np.arange(len(data)) / 59.94
    seated = t < 0.5
    x0 = np.mean((data["p24_x"][seated] + data["p25_x"][seated]) / 2)
    y0 = np.mean((data["p24_y"][seated] + data["p25_y"][seated]) / 2) + 0.15

    def at(n):
        return np.stack([data[f"p{n}_y"] - y0, x0 - data[f"p{n}_x"], data[f"p{n}_z"]], axis=1)

    joints = {name: at(n) for name, n in LANDMARKS.items()}
    joints["pelvis"] = (joints["hip_left"] + joints["hip_right"]) / 2
    return [sample(t[i], {k: v[i] for k, v in joints.items()}) for i in range(len(t))]


def test_a_real_patient_with_pauses_is_timed_within_half_a_second(motion_dir):
    timed = time_trial(samples_of(motion_dir / "tug_f77_mediapipe33.csv"), 0.0)
    assert timed.tug_seconds == pytest.approx(F77_TOTAL, abs=0.5)
    boundaries_as_read(timed.moves, READ)
    # the long stands (at the start and at the far end) are time standing still, not a phase
    assert timed.still == pytest.approx(1.9 + 7.9 + 1.6, abs=1.0)
    parts = timed.reaction + sum(timed.phases.values()) + timed.still
    assert parts == pytest.approx(timed.tug_seconds)


def test_a_sensor_that_swaps_left_and_right_when_she_faces_away_changes_nothing(motion_dir):
    """A Kinect v2 in front of the chair sees her back on the way out: it swaps the sides."""
    real = samples_of(motion_dir / "tug_f77_mediapipe33.csv")
    swapped = [
        s if not 4.0 < s.t < 21.0 else type(s)(s.t, s.height, s.distance, s.heading + math.pi)
        for s in real
    ]
    assert time_trial(swapped, 0.0).moves == time_trial(real, 0.0).moves
