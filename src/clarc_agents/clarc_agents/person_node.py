"""The Person agent: turns Kinect frames into the person's presence and face pose in the DSR
(person node, kinect -RT-> person, person -is_with-> robot). Rules: grammars/person.yaml.

A person counts as seen after ``seen_frames`` frames with a face and as lost after
``lost_frames`` frames without one, so one dropped frame does not end a test. The pose is
written again only when the face moved more than ``move_mm``.

ROS Parameters: seen_frames (2), lost_frames (3), move_mm (50.0). Subscriptions:
clarc/kinect/person. Plus the DSR topics.
"""

from __future__ import annotations

import json
import math
from typing import Dict, List, Optional

from dsr_graph.qos import qos_stream
from dsr_graph.rule_agent import Process
from std_msgs.msg import String

from . import topics
from .agent_node import GrammarAgentNode, declare_float, get_float, main_for


class PersonAgent(GrammarAgentNode):
    GRAMMAR = "person"

    def __init__(self):
        super().__init__("person")
        self.declare_parameter("seen_frames", 2)
        self.declare_parameter("lost_frames", 3)
        declare_float(self, "move_mm", 50.0, "a move smaller than this is not written")
        self.create_subscription(String, topics.KINECT_PERSON, self.on_frame, qos_stream())
        self._present_frames = 0
        self._absent_frames = 0
        self._last_face: Optional[List[float]] = None

    def processes(self) -> Dict[str, Process]:
        return {}

    def _with_robot(self) -> bool:
        return self.dsr.graph.edge("person", "robot", "is_with") is not None

    def on_frame(self, msg: String) -> None:
        if not self.dsr.replica.synced:
            return
        try:
            frame = json.loads(msg.data)
            present = bool(frame["present"])
            face = [float(v) for v in frame["face"]] if present else None
        except (ValueError, KeyError, TypeError) as e:
            self.get_logger().warning(f"unreadable Kinect frame {msg.data!r}: {e}")
            return
        if present:
            self._present_frames, self._absent_frames = self._present_frames + 1, 0
            pose = {"translation": face, "rotation_euler_xyz": [0.0, 0.0, 0.0]}
            if not self._with_robot():
                if self._present_frames >= self.get_parameter("seen_frames").value:
                    self.runner.signal("seen", pose=pose)
                    self._last_face = face
            elif self._last_face is None or math.dist(face, self._last_face) > get_float(self, "move_mm"):
                self.runner.signal("moved", pose=pose)
                self._last_face = face
        else:
            self._absent_frames, self._present_frames = self._absent_frames + 1, 0
            if self._with_robot() and self._absent_frames >= self.get_parameter("lost_frames").value:
                self.runner.signal("lost")  # a repeat before the replica catches up is refused (CAS)


main = main_for(PersonAgent)
