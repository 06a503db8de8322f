"""REP-155's /humans topics and frames for Person and Speech (ROS plumbing; what goes on them is
``clarc_agents/humans.py``), so that ROS for HRI tools (hri_rviz, rqt_human_radar, libhri) see
CLARC's patient.

Person, from each Kinect frame: ``/humans/bodies/tracked`` and ``/humans/persons/tracked``
(hri_msgs/IdsList), ``/humans/bodies/<id>/skeleton2d`` (hri_msgs/Skeleton2D, the joints in the
Kinect's colour image), ``/humans/persons/<id>/body_id`` (std_msgs/String) and
``/humans/persons/<id>/anonymous`` (std_msgs/Bool, true), both latched, and on /tf the frames
``body_<id>`` (the pelvis, x where the body faces, z up) and ``person_<id>`` (at the body, or at
the face when the Kinect sees only a face), both under the Kinect's frame and stamped with the
frame's capture time. Speech: ``/humans/voices/tracked`` (latched: the microphone's one voice,
``anonymous_speaker``) and ``/humans/voices/anonymous_speaker/speech`` (hri_msgs/LiveSpeech) for
each utterance heard.
"""

from __future__ import annotations

import random

from hri_msgs.msg import IdsList, LiveSpeech, NormalizedPointOfInterest2D, Skeleton2D
from rclpy.node import Node
from rclpy.time import Time
from std_msgs.msg import Bool, String
from tf2_msgs.msg import TFMessage

from clarc_agents import humans
from dsr_graph.protocol.tf_frames import Transform
from dsr_graph.ros.qos import qos_latched
from dsr_graph.ros.tf_publisher import TF, qos_tf, tf_message

TRACKED_DEPTH = 10  # ROS4HRI's readers use the default QoS: reliable, 10 deep


def _stamp(seconds: float):
    return Time(nanoseconds=int(seconds * 1e9)).to_msg()


def _ids(ids: list[str], seconds: float) -> IdsList:
    message = IdsList(ids=ids)
    message.header.stamp = _stamp(seconds)
    return message


class PersonHumans:
    """Person's side: the body and the (anonymous) person the Kinect sees."""

    def __init__(self, node: Node, sensor_frame: str, camera: humans.Pinhole, rng=None):
        self.node = node
        self.sensor_frame = sensor_frame
        self.camera = camera
        rng = rng or random.Random()
        self.body = humans.TrackedPart(rng)
        self.person = humans.TrackedPart(rng)
        self._bodies = node.create_publisher(IdsList, humans.BODIES_TRACKED, TRACKED_DEPTH)
        self._persons = node.create_publisher(IdsList, humans.PERSONS_TRACKED, TRACKED_DEPTH)
        self._tf = node.create_publisher(TFMessage, TF, qos_tf())
        self._skeleton = None
        self._person_pubs = []

    def seen(self, stamp: float, joints, yaw: float, face_m) -> None:
        """A frame with the patient in it: ``joints`` (``parse_skeleton``, or None: a face
        only), the body's ``yaw``, the face at ``face_m`` (m, Kinect's frame)."""
        person_id, new_person = self.person.seen()
        if new_person:
            self._person_pubs = self._latched_person(person_id)
        transforms = []
        if joints is not None:
            body_id, new_body = self.body.seen()
            if new_body:
                self._new_body(person_id, body_id)
            translation, rotation = humans.body_pose(joints, yaw)
            body = humans.body_frame(body_id)
            transforms.append(Transform(self.sensor_frame, body, translation, rotation))
            person = Transform(body, humans.person_frame(person_id), (0.0, 0.0, 0.0), _UNIT)
            self._skeleton.publish(self._skeleton2d(joints, stamp))
        else:
            at = tuple(float(v) for v in face_m)
            person = Transform(self.sensor_frame, humans.person_frame(person_id), at, _UNIT)
        transforms.append(person)
        self._tf.publish(tf_message(transforms, _stamp(stamp)))
        self.publish_tracked(stamp)

    def publish_tracked(self, stamp: float) -> None:
        """The ids tracked now (a frame without the patient keeps them until ``lost``)."""
        self._bodies.publish(_ids([self.body.id] if self.body.id else [], stamp))
        self._persons.publish(_ids([self.person.id] if self.person.id else [], stamp))

    def lost(self, stamp: float) -> None:
        """The patient is gone: the body and the person end, their topics with them."""
        if self.body.lost() is not None:
            self.node.destroy_publisher(self._skeleton)
            self._skeleton = None
        if self.person.lost() is not None:
            for publisher in self._person_pubs:
                self.node.destroy_publisher(publisher)
            self._person_pubs = []
        self.publish_tracked(stamp)

    def _latched_person(self, person_id: str) -> list:
        anonymous = self.node.create_publisher(
            Bool, humans.person_topic(person_id, "anonymous"), qos_latched()
        )
        anonymous.publish(Bool(data=True))  # no face recognition: never a known person
        body_id = self.node.create_publisher(
            String, humans.person_topic(person_id, "body_id"), qos_latched()
        )
        return [anonymous, body_id]

    def _new_body(self, person_id: str, body_id: str) -> None:
        if self._skeleton is not None:
            self.node.destroy_publisher(self._skeleton)
        self._skeleton = self.node.create_publisher(
            Skeleton2D, humans.body_topic(body_id, "skeleton2d"), TRACKED_DEPTH
        )
        self._person_pubs[1].publish(String(data=body_id))

    def _skeleton2d(self, joints, stamp: float) -> Skeleton2D:
        message = Skeleton2D()
        message.header.stamp = _stamp(stamp)
        message.header.frame_id = self.sensor_frame
        message.skeleton = [
            NormalizedPointOfInterest2D(x=x, y=y, c=c)
            for x, y, c in humans.skeleton2d(joints, self.camera)
        ]
        return message


_UNIT = (0.0, 0.0, 0.0, 1.0)  # no rotation (x, y, z, w)


class SpeechHumans:
    """Speech's side: what the microphone's one voice said."""

    def __init__(self, node: Node):
        self.node = node
        tracked = node.create_publisher(IdsList, humans.VOICES_TRACKED, qos_latched())
        now = node.get_clock().now().nanoseconds / 1e9
        tracked.publish(_ids([humans.ANONYMOUS_SPEAKER], now))
        self._tracked = tracked
        self._speech = node.create_publisher(
            LiveSpeech, humans.voice_topic(humans.ANONYMOUS_SPEAKER, "speech"), TRACKED_DEPTH
        )

    def heard(self, text: str, confidence: float) -> None:
        message = LiveSpeech(final=text, confidence=float(confidence))
        message.header.stamp = self.node.get_clock().now().to_msg()
        if hasattr(message, "locale"):  # hri_msgs 2.x; an older installed one has no locale
            message.locale = humans.LOCALE
        self._speech.publish(message)
