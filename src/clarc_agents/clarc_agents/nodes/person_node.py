"""The Person agent: turns Kinect frames into the person's presence and face pose in the DSR
(person node, kinect -RT-> person, person -is_with-> robot). Rules: grammars/person.yaml.
The face data also says whether the eyes are closed: while the DSR awaits the answer to an
``eyes`` item (the MMSE's "close your eyes", read on the screen), eyes seen closed for a second
of the patient's time (``behaviours/closed_eyes.py``: a blink is no answer) are its answer
(percept ``eyes_closed``, worth the item's points); a closing seen while that item is on the
screen, just before its window opened, is kept a moment for it.

A person counts as seen after ``seen_frames`` frames with a face and as lost after
``lost_frames`` frames without one, so one dropped frame does not end a test. The pose is
written again only when the face moved more than ``move_mm``. Kinect frames give the face in
millimetres; the DSR holds metres. A frame with a skeleton (Get Up & Go) places the person at
the pelvis and every joint under it, in one transaction (``gug/skeleton.py``); one is in flight
at a time, and the frames that come meanwhile wait for the next one, which carries all of them
(``skeleton_frames``, up to ``max_batch``): a busy machine writes several frames at a time, never
drops one, so a hole in the frames is a hole in what the sensor saw (the gait analyser voids a
trial only for that). The subscription keeps up to 1 s of frames at 300 a second for the same
reason.

ROS Parameters: seen_frames (2), lost_frames (3) and lost_seconds (0.5 of the patient's time:
both, before the person counts as lost; a tracker loses a body for a moment now and then),
move_mm (50.0), max_batch (600: frames in one
transaction; older ones are dropped past it and the gap shows), camera_width (640),
camera_height (480) and camera_focal (525.0 pixels: the Kinect's colour camera, for the
skeleton in its image). Subscriptions: clarc/kinect/person. Publishers: REP-155's
/humans/bodies and /humans/persons topics and their /tf frames (nodes/humans_topics.py), from
every frame whether or not the DSR holds the person. Plus the DSR topics.
"""

from __future__ import annotations

import math
import time
from typing import Any

from clarc_agents import topics
from clarc_agents.behaviours.closed_eyes import EyesAnswer
from clarc_agents.gug.posture import PostureTracker, pelvis_in_room
from clarc_agents.gug.skeleton import SENSOR, frames_tx, heading, parse_skeleton
from clarc_agents.humans import Absence, Pinhole
from clarc_agents.nodes.grammar_agent import GrammarAgentNode
from clarc_agents.nodes.humans_topics import PersonHumans
from dsr_graph.formats.units import PER_METRE
from dsr_graph.ros.dsr_node import main_for
from dsr_graph.ros.json_topics import subscribe_json
from dsr_graph.ros.parameters import declare, float_param, param
from dsr_graph.ros.qos import qos_every_frame
from dsr_graph.rules.runner import Process

DEVICE_UNIT = "mm"  # of clarc/kinect/person's face
SENSOR_HOLE = 0.5  # s of the patient's time between skeleton frames that Person reports


class PersonAgent(GrammarAgentNode):
    GRAMMAR = "person"

    NAME = "person"

    @classmethod
    def declare_node_parameters(cls, node) -> None:
        super().declare_node_parameters(node)
        declare(
            node, "seen_frames", 2, "frames with a face before the person counts as seen", minimum=1
        )
        declare(
            node,
            "lost_frames",
            3,
            "frames without a face before the person counts as lost",
            minimum=1,
        )
        declare(
            node,
            "lost_seconds",
            0.5,
            "seconds of the patient's time without a body before the person counts as lost",
            minimum=0.0,
        )
        declare(node, "move_mm", 50.0, "a move smaller than this is not written", minimum=0.0)
        declare(node, "max_batch", 600, "skeleton frames in one transaction, at most", minimum=1)
        # the Kinect's colour camera, where /humans/bodies/<id>/skeleton2d places the joints
        declare(node, "camera_width", 640, "colour image width (pixels)", minimum=1)
        declare(node, "camera_height", 480, "colour image height (pixels)", minimum=1)
        declare(node, "camera_focal", 525.0, "colour camera focal length (pixels)", minimum=1.0)

    def __init__(self):
        super().__init__()
        self._present_frames = 0
        self._absence = Absence()  # of the person the DSR holds
        self._humans_absence = Absence()  # of the body and person on the /humans topics
        self.humans: PersonHumans | None = None
        self._last_face: list[float] | None = None
        self._skeleton_in_flight = False
        self._waiting: list = []  # skeleton frames for the next transaction, oldest first
        self._last_written: float | None = None  # the capture stamp of the last frame taken
        self.skeletons_dropped = 0
        self._posture = PostureTracker(self.scale)
        self._eyes = EyesAnswer(self.scale)

    def processes(self) -> dict[str, Process]:
        return {}

    def setup(self) -> None:
        # every frame (a Get Up & Go's trial needs them all), kept while Person is busy
        kept = qos_every_frame(topics.KINECT_FRAMES_KEPT)
        camera = Pinhole(
            param(self, "camera_width"), param(self, "camera_height"), param(self, "camera_focal")
        )
        self.humans = PersonHumans(self, SENSOR, camera)
        subscribe_json(self, topics.KINECT_PERSON, self.on_frame, kept)
        self.dsr.describe(can_do=["track the person"], listens_to=[topics.KINECT_PERSON])
        self.dsr.add_listener(lambda d, r: self._answer_eyes(self._eyes.on_graph(self.dsr.graph)))
        super().setup()

    def _with_robot(self) -> bool:
        return self.dsr.graph.edge("person", "robot", "is_with") is not None

    def on_frame(self, frame: dict[str, Any]) -> None:
        present = frame["present"]
        if not isinstance(present, bool):
            raise ValueError(f"present must be true or false, got {present!r}")
        joints = parse_skeleton(frame["skeleton"]) if present and "skeleton" in frame else None
        face = [float(v) for v in frame["face"]] if present else None
        if face is not None and (len(face) != 3 or not all(math.isfinite(v) for v in face)):
            raise ValueError(f"face must be 3 finite numbers (mm), got {frame['face']!r}")
        eyes = frame.get("eyes", "open")
        if eyes not in ("open", "closed"):
            raise ValueError(f"eyes must be open or closed, got {eyes!r}")
        stamp = self._stamp_of(frame)
        # the Kinect speaks millimetres (its SDK's unit), the DSR metres: converted here, once
        face_m = [v / PER_METRE[DEVICE_UNIT] for v in face] if face is not None else None
        self._to_humans(stamp, joints, face_m)  # what the sensor sees, whatever the DSR holds
        if not self.dsr.replica.synced:
            return
        if present:
            self._present_frames = self._present_frames + 1
            self._absence.present()
            self._answer_eyes(self._eyes.see(self.dsr.graph, eyes == "closed", stamp))
            metres = joints["pelvis"][0].tolist() if joints is not None else face_m
            pose = {"translation": metres, "rotation_euler_xyz": [0.0, 0.0, 0.0]}
            if self._with_robot() and joints is not None:  # the person is where the pelvis is
                self._write_skeleton(joints, float(frame.get("stamp", 0.0)))
                self._follow_posture(joints, float(frame.get("stamp", 0.0)))
            elif not self._with_robot():
                self._last_written = None  # not written: no hole in what Person writes
                if self._present_frames >= param(self, "seen_frames"):
                    self.runner.signal("seen", pose=pose)
                    self._last_face = face
            elif self._last_face is None or math.dist(face, self._last_face) > float_param(
                self, "move_mm"
            ):
                self.runner.signal("moved", pose=pose)
                self._last_face = face
        else:
            self._last_written = None  # a frame without a body is not a hole in the stream
            self._eyes.see(self.dsr.graph, False, stamp)
            self._absence.absent(stamp)
            self._present_frames = 0
            if self._with_robot() and self._gone(self._absence, stamp):
                self.runner.signal(
                    "lost"
                )  # a repeat before the replica catches up is refused (CAS)
        if frame.get("range_warning"):
            self.get_logger().warning(
                "the person is beyond the Kinect's range (4.5 m): its joints are less sure",
                throttle_duration_sec=10.0,
            )

    def _gone(self, absence: Absence, stamp: float) -> bool:
        """Lost: ``lost_frames`` frames and ``lost_seconds`` of the patient's time without."""
        seconds = float_param(self, "lost_seconds") * self.scale
        return absence.lost(stamp, param(self, "lost_frames"), seconds)

    def _to_humans(self, stamp: float, joints, face_m) -> None:
        """REP-155's topics and frames (nodes/humans_topics.py) for this frame."""
        if face_m is not None:
            self._humans_absence.present()
            yaw = heading(joints) if joints is not None else 0.0
            self.humans.seen(stamp, joints, yaw, face_m)
            return
        self._humans_absence.absent(stamp)
        if self._gone(self._humans_absence, stamp):
            self.humans.lost(stamp)
        else:
            self.humans.publish_tracked(stamp)

    @staticmethod
    def _stamp_of(frame: dict[str, Any]) -> float:
        """When the sensor took ``frame`` (its ``stamp``), else now."""
        stamp = frame.get("stamp")
        if isinstance(stamp, (int, float)) and not isinstance(stamp, bool) and math.isfinite(stamp):
            return float(stamp)
        return time.time()

    def _answer_eyes(self, points: int | None) -> None:
        if points is not None and self._with_robot():  # once: the rule takes the window
            self.runner.signal("eyes_closed", points=points)

    def _follow_posture(self, joints, stamp: float) -> None:
        """Sitting, standing or walking, from the pelvis in the room (its height above the
        floor): a change is the percept ``posture`` (grammars/person.yaml writes it)."""
        posture = self._posture.update(stamp, pelvis_in_room(self.dsr.graph, joints))
        if posture is not None:
            self.runner.signal("posture", posture=posture)

    def _write_skeleton(self, joints, stamp: float) -> None:
        last = self._waiting[-1][1] if self._waiting else self._last_written
        hole = (stamp - last) / self.scale if last is not None else 0.0
        if hole > SENSOR_HOLE:  # said where it is seen, so a voided trial's hole can be placed
            self.get_logger().warning(
                f"no skeleton frame came from the Kinect for {hole:.2f} s of the patient's time "
                "(by the frames' capture stamps)"
            )
        self._last_written = stamp
        self._waiting.append((joints, stamp))
        extra = len(self._waiting) - param(self, "max_batch")
        if extra > 0:  # the DSR stalled for longer than max_batch frames: the gap will show
            self.skeletons_dropped += extra
            del self._waiting[:extra]
            self.get_logger().warning(
                f"{self.skeletons_dropped} skeleton frame(s) dropped so far: the DSR is not "
                "taking them",
                throttle_duration_sec=5.0,
            )
        self._send_skeletons()

    def _send_skeletons(self) -> None:
        if self._skeleton_in_flight or not self._waiting:
            return
        frames, self._waiting = self._waiting, []
        self._skeleton_in_flight = True

        def done(result) -> None:
            self._skeleton_in_flight = False
            if not result.accepted:
                self.get_logger().warning(
                    f"{len(frames)} skeleton frame(s) refused: {result.error}"
                )
            self._send_skeletons()

        self.dsr.send(frames_tx(self.dsr.graph, frames), done)


main = main_for(PersonAgent)
