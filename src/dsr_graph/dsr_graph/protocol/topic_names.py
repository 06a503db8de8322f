"""Topic names derived from DSR node names (pure; no ROS import).

A node name that is already a safe ROS name token (a letter, then letters, digits or
underscores) is used as it is: ``/dsr/pose/robot``. Any other name (``Wall 2``, ``1000``,
``cámara``) becomes a readable token plus a short hash of the exact name, so two different
names never share a topic: runs of other characters become ``_``, a leading digit gets an ``n``
prefix, and ``_h`` + the first 8 hex digits of the name's SHA-1 is appended
(``Wall 2`` -> ``Wall_2_h86e47518``). ``dsr ros`` lists the pose topics with their node names.
"""

from __future__ import annotations

import hashlib
import re

_SAFE = re.compile(r"[A-Za-z][A-Za-z0-9_]*\Z")
_UNSAFE_RUN = re.compile(r"[^A-Za-z0-9]+")

# Relative names (they resolve in the node's namespace and can be remapped).
TRANSACTIONS = "dsr/transactions"  # + /<node name>: std_msgs/String, JSON requests -> server
# + /<node name>: std_msgs/Empty, one message per server matched: its DDS liveliness tells the
# server the agent is in reach (protocol/presence.py), kept off the request topic, whose every
# message a second reader would cost (issue 35)
PRESENCE = "dsr/presence"
DELTAS = "dsr/deltas"  # std_msgs/String, JSON accepted deltas, in seq order <- server
# dsr_msgs/Blob: the bytes of large binary values the JSON references (protocol/blobs.py): from
# the server beside its deltas; + /<node name>: from an agent beside its requests
BLOBS = "dsr/blobs"
# + /<node name>: dsr_msgs/Blob, the bytes of the sensor data (volatile values) an agent writes,
# from the agent straight to the replicas that want them: the server never reads them
SENSOR_BLOBS = "dsr/sensor_blobs"
REJECTIONS = "dsr/rejections"  # std_msgs/String, JSON {id, agent, reason, error} <- server
ALARMS = "dsr/alarms"  # std_msgs/String, JSON {kind, topic, intruders, message} <- server
HEARTBEAT = "dsr/heartbeat"  # std_msgs/String, JSON {seq, stamp, boot, durable, ...} <- server
DURABLE = "dsr/durable"  # std_msgs/String, JSON {boot, durable} after each group commit <- server
GET_ATTRIBUTE = "dsr/get_attribute"  # dsr_msgs/srv/GetAttribute
GET_BLOB = "dsr/get_blob"  # dsr_msgs/srv/GetBlob: a binary value's bytes (+ /<node name>:
# the sensor data that agent wrote, which only it holds)
GET_NODE = "dsr/get_node"  # dsr_msgs/srv/GetNode
GET_SNAPSHOT = "dsr/get_snapshot"  # dsr_msgs/srv/GetSnapshot
GET_TRANSFORM = "dsr/get_transform"  # dsr_msgs/srv/GetTransform
POSE_PREFIX = "dsr/pose"  # geometry_msgs/PoseStamped per geometric node, latched
MARKERS = "dsr/markers"  # visualization_msgs/MarkerArray: the graph drawn for RViz, latched


def name_token(name: str) -> str:
    """A valid ROS topic token for a node name; injective in practice (see module doc)."""
    if _SAFE.match(name):
        return name
    readable = _UNSAFE_RUN.sub("_", name).strip("_")
    if not readable or readable[0].isdigit():
        readable = "n" + readable
    digest = hashlib.sha1(name.encode("utf-8")).hexdigest()[:8]
    return f"{readable}_h{digest}"


def pose_topic(name: str, prefix: str = POSE_PREFIX) -> str:
    """Relative topic name of a node's PoseStamped (``dsr/pose/<token>``)."""
    return f"{prefix}/{name_token(name)}"
