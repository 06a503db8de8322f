"""The Kinect stand-in: a frame every 1/rate_hz seconds saying whether a person is in front of
the robot, where their face is (mm, in the Kinect's frame, with a little jitter) and whether the
eyes are open or closed, following the simulated patient. In a Get Up & Go trial (the patient
says so on clarc/sim/patient/trial) it tracks the whole skeleton instead: skeleton_hz frames per
second of the patient's time, each with every joint (mm, in the Kinect's frame) and its
confidence, as a Kinect v2 would give them (``skeleton_frames.KinectModel``: slow noise of the
scenario's size, confidence falling with range and occlusion, a range warning beyond 4.5 m, the
sides swapped when the body faces away), the scenario's lost frames and its brief tracking losses
(frames without a body, 0.1 to 0.35 s each), or a patient who cannot rise (``rises: false``:
seated as before "go"); or, when the trial
names a skeleton recording, its frames as recorded, placed at the trial's chair and played from
the recording's ``offset`` at "go", at the run's pace (before "go": its first frame; after its
end: its last). Skeleton frames are captured on the sensor's own clock, every 1/skeleton_hz s of
the patient's time, each stamped when it was captured: a stand-in held up by a busy machine
delivers the frames it owes late, in a burst, as a real sensor's driver does, never a hole
(up to BACKLOG_S of the patient's time; beyond that they are gone).

With ``camera_hz`` above 0 its cameras run too (``camera_images.CameraModel``): a colour and a
depth image of ``camera_size`` every 1/camera_hz s of wall time (a camera's own rate, whatever
the session's pace), the patient drawn where their face is.

ROS Parameters: rate_hz (30, as a Kinect), skeleton_hz (30, of the patient's time),
time_scale (1.0), trial_place ([x, y, z] mm and yaw rad of the trial's frame in the Kinect's:
the floor under the front of the Get Up & Go chair, facing the walk; default [4500, 0, -1200,
pi], the CLARC room's gug_chair), camera_hz (0: no images), camera_size ([640, 480]). Subscriptions:
clarc/sim/patient/presence, clarc/sim/patient/trial (latched). Publishers: clarc/kinect/person
(reliable: a Get Up & Go needs every frame), clarc/kinect/rgb and clarc/kinect/depth
(sensor_msgs/Image, best effort).
"""

from __future__ import annotations

import array
import math
import random
import time
from typing import Any

import numpy as np
from sensor_msgs.msg import Image
from std_msgs.msg import String

from clarc_agents import topics
from clarc_sim import sim_topics
from clarc_sim.devices.camera_images import CameraModel
from clarc_sim.devices.skeleton_frames import (
    KinectModel,
    TrialPlace,
    dropped,
    recorded,
    skeleton,
    tracking_losses,
)
from clarc_sim.patient.gait_motion import Motion
from clarc_sim.patient.skeleton_recording import placed, read
from dsr_graph.ros.dsr_node import DsrNode, main_for
from dsr_graph.ros.json_topics import publish_json, subscribe_json
from dsr_graph.ros.parameters import declare, declare_time_scale, float_param, param
from dsr_graph.ros.qos import qos_every_frame, qos_images, qos_latched

BACKLOG_S = 60.0  # seconds of the patient's time of frames a late stand-in still delivers
PIPELINE_S = 0.5  # seconds of wall time between taking a skeleton frame and delivering it


class KinectStandIn(DsrNode):
    NAME = "kinect"

    @classmethod
    def declare_node_parameters(cls, node) -> None:
        declare(node, "rate_hz", 30.0, "frames per second", read_only=True, minimum=0.1)
        declare(
            node,
            "skeleton_hz",
            30.0,
            "skeleton frames per second of the patient's time",
            read_only=True,
            minimum=0.1,
        )
        declare_time_scale(node)
        declare(
            node,
            "camera_hz",
            0.0,
            "colour and depth images per second of wall time (0: the cameras are off)",
            read_only=True,
            minimum=0.0,
        )
        declare(
            node,
            "camera_size",
            [640, 480],
            "width and height of the camera images, pixels",
            read_only=True,
        )
        declare(
            node,
            "trial_place",
            [4500.0, 0.0, -1200.0, math.pi],
            "the Get Up & Go trial's frame in the Kinect's: x, y, z (mm), yaw (rad)",
            read_only=True,
        )

    def __init__(self):
        super().__init__()
        self.presence: dict[str, Any] = {"present": False, "face": [0.0, 0.0, 0.0]}
        self.trial: dict[str, Any] | None = None
        self._recordings: dict[str, Any] = {}  # path: the recording, placed
        self._random = random.Random(7)

    def setup(self) -> None:
        # reliable and deep: a reader that needs every frame gets them on a busy machine too
        self._frames = self.create_publisher(
            String, topics.KINECT_PERSON, qos_every_frame(topics.KINECT_FRAMES_KEPT)
        )
        subscribe_json(self, sim_topics.PATIENT_PRESENCE, self.on_presence, qos_latched())
        subscribe_json(self, sim_topics.PATIENT_TRIAL, self.on_trial, qos_latched())
        self.place = TrialPlace(*(float(v) for v in param(self, "trial_place")))
        self.scale = float_param(self, "time_scale") or 1.0
        self._period = self.scale / float_param(self, "skeleton_hz")  # s of wall time per frame
        self.create_timer(1.0 / float_param(self, "rate_hz"), self.on_frame)
        self._skeleton_timer = None  # made with the first trial: a Barthel test needs none
        self._next_capture: float | None = None  # when the sensor takes its next frame
        if float_param(self, "camera_hz") > 0:
            width, height = (int(v) for v in param(self, "camera_size"))
            if not (16 <= width <= 4096 and 16 <= height <= 4096):
                raise ValueError(
                    f"parameter camera_size: 16 to 4096 pixels each, got {width}x{height}"
                )
            self._camera = CameraModel(width, height)
            self._rgb = self.create_publisher(Image, topics.KINECT_RGB, qos_images())
            self._depth = self.create_publisher(Image, topics.KINECT_DEPTH, qos_images())
            self.images_taken = 0
            self.create_timer(1.0 / float_param(self, "camera_hz"), self.on_camera)

    def on_presence(self, doc: dict[str, Any]) -> None:
        self.presence = {
            "present": bool(doc["present"]),
            "face": [float(v) for v in doc.get("face", [0, 0, 0])],
            "eyes": "closed" if doc.get("eyes_closed") else "open",
        }

    def on_trial(self, doc: dict[str, Any]) -> None:
        recording = None
        if doc.get("recording") is not None:
            recording = self._recordings.get(doc["recording"])
            if recording is None:  # read and placed once: a trial repeated plays it again
                recording = placed(read(doc["recording"]))
                self._recordings[doc["recording"]] = recording
        motion = doc.get("motion")
        self.trial = {
            "motion": None
            if motion is None
            else Motion(**{k: float(v) for k, v in motion.items()}),
            "recording": recording,
            "offset": float(doc.get("offset", 0.0)),
            "go": None if doc.get("go") is None else float(doc["go"]),
            "drop_rate": float(doc.get("drop_rate", 0.0)),
            "rises": doc.get("rises", True) is not False,
            "sensor": KinectModel(self._random, float(doc.get("noise_mm", 0.0))),
        }
        length = recording.duration if recording is not None else self.trial["motion"].total
        self.trial["losses"] = tracking_losses(
            self._random, int(doc.get("tracking_losses", 0)), length
        )
        if self._skeleton_timer is None:
            self._skeleton_timer = self.create_timer(self._period, self.on_skeleton_frame)

    def on_frame(self) -> None:
        if self.trial is not None and self.presence["present"]:
            return  # the skeleton frames say it all
        frame: dict[str, Any] = {"present": self.presence["present"], "stamp": time.time()}
        if frame["present"]:
            frame["face"] = [v + self._random.uniform(-5, 5) for v in self.presence["face"]]
            frame["eyes"] = self.presence["eyes"]
        publish_json(self._frames, frame)

    def on_camera(self) -> None:
        """A colour and a depth image, stamped when taken."""
        present = self.presence["present"]
        rgb, depth = self._camera.frame(
            self.images_taken, self.presence["face"] if present else None
        )
        self.images_taken += 1
        stamp = self.get_clock().now().to_msg()
        self._rgb.publish(image_message(rgb, "rgb8", stamp))
        self._depth.publish(image_message(depth, "16UC1", stamp))

    def on_skeleton_frame(self) -> None:
        """Every frame the sensor took since the last call, each at its capture time, delivered
        ``PIPELINE_S`` after it (a sensor's pipeline): a frame is drawn once the stand-in has
        heard of a "go" said before it was taken, so a patient's trial never starts late in the
        frames because the news of "go" reached the stand-in late."""
        now = time.time() - PIPELINE_S
        oldest = now - BACKLOG_S * self.scale
        if self._next_capture is None or self._next_capture < oldest:
            if self._next_capture is not None:
                self.get_logger().warning(
                    f"held up for {(now - self._next_capture) / self.scale:.2f} s of the "
                    f"patient's time: frames older than {BACKLOG_S:g} s are lost"
                )
            self._next_capture = max(self._next_capture or now, oldest)
        while self._next_capture <= now:
            self._capture(self._next_capture)
            self._next_capture += self._period

    def _capture(self, now: float) -> None:
        trial = self.trial
        if trial is None or not self.presence["present"]:
            return
        if dropped(self._random, trial["drop_rate"]):
            return
        t = -1.0 if trial["go"] is None else (now - trial["go"]) / self.scale
        if not trial["rises"]:
            t = min(t, -1.0)  # stays seated as before "go"
        if any(start <= t < end for start, end in trial["losses"]):
            publish_json(self._frames, {"present": False, "stamp": now})  # tracking lost
            return
        if trial["recording"] is not None:
            ideal = recorded(trial["recording"], t + trial["offset"], self.place)
            if ideal is None:  # no body (or no pelvis) in the recorded frame
                publish_json(self._frames, {"present": False, "stamp": now})
                return
        else:
            ideal = skeleton(trial["motion"], t, self.place)
        joints, far = trial["sensor"].see(ideal, t)
        face = joints.get("head", joints["pelvis"])["p"]
        frame = {"present": True, "face": face, "stamp": now, "skeleton": joints}
        if far:
            frame["range_warning"] = True
        publish_json(self._frames, frame)


def image_message(pixels: np.ndarray, encoding: str, stamp) -> Image:
    """A sensor_msgs/Image of ``pixels`` (rows x columns [x channels]), little-endian, the
    bytes copied once."""
    msg = Image(encoding=encoding, height=pixels.shape[0], width=pixels.shape[1])
    msg.header.stamp, msg.header.frame_id = stamp, "kinect"
    msg.step = pixels.shape[1] * pixels.itemsize * (pixels.shape[2] if pixels.ndim == 3 else 1)
    data = array.array("B")
    little = np.ascontiguousarray(pixels, dtype=pixels.dtype.newbyteorder("<"))
    data.frombytes(memoryview(little).cast("B"))
    msg.data = data
    return msg


main = main_for(KinectStandIn)
