"""Our device and event topics carry JSON objects in ``std_msgs/String``. A malformed message
never kills a node: it is refused with one warning that names the topic and what is wrong
(read by ``formats/safe_json``: size in bytes, depth, NaN and huge numbers bounded)."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from rclpy.node import Node
from rclpy.qos import QoSProfile
from std_msgs.msg import String

from dsr_graph.formats.safe_json import DEFAULT_MAX_BYTES, READING_ERRORS, loads_object
from dsr_graph.model.binary import dumps

MAX_QUOTED = 200  # characters of a bad message quoted in the warning


def subscribe_json(
    node: Node,
    topic: str,
    callback: Callable[[dict[str, Any]], None],
    qos: QoSProfile,
    max_bytes: int = DEFAULT_MAX_BYTES,
):
    """Subscribe ``callback(doc)`` to a topic of JSON objects. A message that is not a JSON
    object, or that the callback cannot read (a missing field, a wrong type: ``KeyError``,
    ``TypeError``, ``ValueError``, ``AttributeError``, ``IndexError``), is refused with a
    warning; any other exception is a bug, which ``DsrNode``'s guard of every subscription logs
    with its traceback, and the node goes on."""

    def on_message(msg: String) -> None:
        try:
            callback(loads_object(msg.data, max_bytes))
        except READING_ERRORS as e:
            reason = f"missing field {e}" if isinstance(e, KeyError) else str(e)
            node.get_logger().warning(
                f"ignored a message on {topic}: {reason}: {msg.data[:MAX_QUOTED]!r}"
            )

    return node.create_subscription(String, topic, on_message, qos)


def publish_json(publisher, doc: dict[str, Any]) -> None:
    publisher.publish(String(data=dumps(doc)))
