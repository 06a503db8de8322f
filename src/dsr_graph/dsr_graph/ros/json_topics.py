"""Our device and event topics carry JSON objects in ``std_msgs/String``. A malformed message
never kills a node: it is refused with one warning that names the topic and what is wrong."""

from __future__ import annotations

import json
from collections.abc import Callable
from typing import Any

from rclpy.node import Node
from rclpy.qos import QoSProfile
from std_msgs.msg import String

MAX_QUOTED = 200  # characters of a bad message quoted in the warning


def subscribe_json(
    node: Node, topic: str, callback: Callable[[dict[str, Any]], None], qos: QoSProfile
):
    """Subscribe ``callback(doc)`` to a topic of JSON objects. A message that is not a JSON
    object, or that the callback cannot read (a missing field, a wrong type: ``KeyError``,
    ``TypeError``, ``ValueError``), is refused with a warning."""

    def on_message(msg: String) -> None:
        try:
            doc = json.loads(msg.data)
            if not isinstance(doc, dict):
                raise ValueError(f"a JSON object was expected, got {type(doc).__name__}")
            callback(doc)
        except (ValueError, KeyError, TypeError) as e:
            reason = f"missing field {e}" if isinstance(e, KeyError) else str(e)
            node.get_logger().warning(
                f"ignored a message on {topic}: {reason}: {msg.data[:MAX_QUOTED]!r}"
            )

    return node.create_subscription(String, topic, on_message, qos)


def publish_json(publisher, doc: dict[str, Any]) -> None:
    publisher.publish(String(data=json.dumps(doc)))
