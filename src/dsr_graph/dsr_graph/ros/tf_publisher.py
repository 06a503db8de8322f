"""The DSR's RT tree on /tf and /tf_static (tf2_msgs/TFMessage) for RViz, Foxglove and any tf2
listener; which edge goes where is protocol/tf_frames.py. QoS as tf2_ros's broadcasters:
/tf reliable and volatile, /tf_static reliable and transient-local (latched). The dynamic
transforms are sent again with each heartbeat, so a listener's buffer never lets a frame that
stopped moving expire."""

from __future__ import annotations

from geometry_msgs.msg import TransformStamped
from rclpy.node import Node
from rclpy.qos import DurabilityPolicy, HistoryPolicy, QoSProfile, ReliabilityPolicy
from tf2_msgs.msg import TFMessage

from dsr_graph.model.graph import Graph
from dsr_graph.protocol.tf_frames import TfBook, Transform

TF = "/tf"  # absolute, as tf2 has them: never namespaced
TF_STATIC = "/tf_static"


def tf_message(transforms: list[Transform], stamp) -> TFMessage:
    out = []
    for t in transforms:
        m = TransformStamped()
        m.header.stamp = stamp
        m.header.frame_id = t.parent
        m.child_frame_id = t.child
        tr, rot = m.transform.translation, m.transform.rotation
        tr.x, tr.y, tr.z = t.translation
        rot.x, rot.y, rot.z, rot.w = t.rotation
        out.append(m)
    return TFMessage(transforms=out)


def qos_tf() -> QoSProfile:
    """/tf's, as tf2_ros's TransformBroadcaster offers it: reliable, volatile, 100 deep."""
    return QoSProfile(
        depth=100,
        durability=DurabilityPolicy.VOLATILE,
        reliability=ReliabilityPolicy.RELIABLE,
        history=HistoryPolicy.KEEP_LAST,
    )


class TfPublisher:
    def __init__(self, node: Node, graph: Graph):
        self.node = node
        self.book = TfBook(graph)
        reliable = dict(reliability=ReliabilityPolicy.RELIABLE, history=HistoryPolicy.KEEP_LAST)
        self._tf = node.create_publisher(TFMessage, TF, qos_tf())
        self._static = node.create_publisher(
            TFMessage,
            TF_STATIC,
            QoSProfile(depth=1, durability=DurabilityPolicy.TRANSIENT_LOCAL, **reliable),
        )
        self.send_static(graph)

    def _now(self):
        return self.node.get_clock().now().to_msg()

    def send_static(self, graph: Graph) -> None:
        self._static.publish(tf_message(self.book.static_transforms(graph), self._now()))

    def on_delta(self, graph: Graph, delta: dict) -> None:
        now, static_changed = self.book.update(graph, delta)
        if static_changed:
            self.send_static(graph)
        if now and self._tf.get_subscription_count():  # volatile: nobody listens, nobody lacks it
            self._tf.publish(tf_message(now, self._now()))

    def refresh(self, graph: Graph) -> None:
        """The dynamic transforms again, newly stamped (the heartbeat calls it)."""
        if not self._tf.get_subscription_count():
            return
        dynamic = self.book.dynamic_transforms(graph)
        if dynamic:
            self._tf.publish(tf_message(dynamic, self._now()))
