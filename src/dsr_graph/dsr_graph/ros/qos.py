"""QoS profiles of the DSR topics, chosen on purpose and named (ROS plumbing)."""

from rclpy.duration import Duration
from rclpy.qos import (
    DurabilityPolicy,
    HistoryPolicy,
    LivelinessPolicy,
    QoSProfile,
    ReliabilityPolicy,
)

from dsr_graph.protocol.presence import PRESENCE_LEASE

# Deep enough to absorb a burst of a few seconds at benchmark rates; a consumer that still
# falls behind sees a gap in seq and resynchronises from a snapshot.
STREAM_DEPTH = 10000


def qos_stream() -> QoSProfile:
    """Ordered change streams (requests, deltas, rejections): reliable, deep, volatile."""
    return QoSProfile(
        history=HistoryPolicy.KEEP_LAST,
        depth=STREAM_DEPTH,
        reliability=ReliabilityPolicy.RELIABLE,
        durability=DurabilityPolicy.VOLATILE,
    )


def qos_presence() -> QoSProfile:
    """An agent's presence topic, both ends: a short liveliness lease that the middleware asserts
    (AUTOMATIC), so the server can tell when the agent is out of reach (protocol/presence.py);
    only one empty message is published each time a server matches it (asserting liveliness at
    once), so best effort and depth 1. A topic of its own: a second reader on the request topic
    cost every request a second delivery (issue 35)."""
    return QoSProfile(
        history=HistoryPolicy.KEEP_LAST,
        depth=1,
        reliability=ReliabilityPolicy.BEST_EFFORT,
        durability=DurabilityPolicy.VOLATILE,
        liveliness=LivelinessPolicy.AUTOMATIC,
        liveliness_lease_duration=Duration(seconds=PRESENCE_LEASE),
    )


def qos_every_frame(depth: int) -> QoSProfile:
    """A sensor stream whose reader needs every frame (Person's skeleton in a Get Up & Go: a
    hole voids the trial): reliable, so a frame lost on a busy machine is sent again, and
    ``depth`` deep on each side. Publishing so, a sensor still serves best-effort readers."""
    return QoSProfile(
        history=HistoryPolicy.KEEP_LAST,
        depth=depth,
        reliability=ReliabilityPolicy.RELIABLE,
        durability=DurabilityPolicy.VOLATILE,
    )


BLOB_DEPTH = 8  # blobs a side holds for a slow reader: a camera's quarter second at 30 Hz


def qos_blobs() -> QoSProfile:
    """Binary values beside the deltas (dsr/blobs): reliable like the stream they go with, but
    shallow, since each may be megabytes; one a slow reader misses leaves its value unfetched
    (a volatile one is replaced by the next frame anyway)."""
    return QoSProfile(
        history=HistoryPolicy.KEEP_LAST,
        depth=BLOB_DEPTH,
        reliability=ReliabilityPolicy.RELIABLE,
        durability=DurabilityPolicy.VOLATILE,
    )


def qos_images() -> QoSProfile:
    """A camera's images: best effort and the newest two, as ROS's sensor-data profile has it
    for a reader that wants the latest image rather than every one late."""
    return QoSProfile(
        history=HistoryPolicy.KEEP_LAST,
        depth=2,
        reliability=ReliabilityPolicy.BEST_EFFORT,
        durability=DurabilityPolicy.VOLATILE,
    )


def qos_latched() -> QoSProfile:
    """State (poses, heartbeat): the last value reaches late joiners."""
    return QoSProfile(
        history=HistoryPolicy.KEEP_LAST,
        depth=1,
        reliability=ReliabilityPolicy.RELIABLE,
        durability=DurabilityPolicy.TRANSIENT_LOCAL,
    )


def qos_matching(publishers, depth: int = 100) -> QoSProfile:
    """A subscription that hears every publisher of a topic (as ``ros2 bag`` and ``ros2 topic
    echo`` choose it): best effort if any publisher is, transient local (the latched value) only
    if all are. ``publishers``: ``Node.get_publishers_info_by_topic``."""
    qos = QoSProfile(depth=depth)
    if any(p.qos_profile.reliability == ReliabilityPolicy.BEST_EFFORT for p in publishers):
        qos.reliability = ReliabilityPolicy.BEST_EFFORT
    if publishers and all(
        p.qos_profile.durability == DurabilityPolicy.TRANSIENT_LOCAL for p in publishers
    ):
        qos.durability = DurabilityPolicy.TRANSIENT_LOCAL
    return qos
