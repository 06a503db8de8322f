"""Blob topics (ROS plumbing for ``protocol/blobs.py``): the bytes of large binary values, as
``dsr_msgs/Blob`` (CDR), beside the JSON that references them by digest.

``BlobInbox`` keeps what arrives on one or more topics in a ``BlobCache``, each blob only if
its bytes hash to its digest (anyone may publish on a topic; only the digest in a signed
request or delta makes bytes count). The server has one per agent (``dsr/blobs/<node name>``,
found as agents appear), an agent one for the server's ``dsr/blobs``.
"""

from __future__ import annotations

import array
from collections.abc import Callable

from dsr_graph.protocol.blobs import BlobCache
from dsr_graph.protocol.topic_names import BLOBS
from dsr_graph.ros.qos import qos_blobs
from dsr_msgs.msg import Blob

BLOB_TYPE = "dsr_msgs/msg/Blob"


def blob_message(digest: str, data: bytes | array.array) -> Blob:
    """A blob as its message: bytes copied once (not element by element), a received blob's
    array (``BlobInbox`` keeps the message's own) not copied at all."""
    msg = Blob(digest=digest)  # (its constructor would copy data once more)
    msg.data = (
        data if isinstance(data, array.array) and data.typecode == "B" else array.array("B", data)
    )
    return msg


class BlobInbox:
    def __init__(
        self,
        node,
        cache: BlobCache,
        on_blob: Callable[[str], None] = lambda digest: None,
        max_bytes: int | None = None,
    ):
        self.node, self.cache, self.on_blob, self.max_bytes = node, cache, on_blob, max_bytes
        self.dropped = 0  # blobs refused: too big, or not what their digest says
        self._subs: dict[str, object] = {}

    def listen(self, topic: str) -> None:
        if topic not in self._subs:
            self._subs[topic] = self.node.create_subscription(
                Blob, topic, self._on_blob, qos_blobs()
            )

    def listen_to_agents(
        self, topics: list[tuple[str, list[str]]], families: tuple[str, ...] = (BLOBS,)
    ) -> None:
        """Subscribe to every agent's ``<family>/<node name>`` among ``topics`` (the ROS graph's
        names and types: the server looks once for these and its request topics), for each of
        ``families``: ``dsr/blobs`` (the server), also ``dsr/sensor_blobs`` (a replica)."""
        for family in families:
            prefix = self.node.resolve_topic_name(family) + "/"
            for topic, types in topics:
                owner = topic[len(prefix) :]
                if topic.startswith(prefix) and "/" not in owner and types == [BLOB_TYPE]:
                    self.listen(topic)

    def _on_blob(self, msg: Blob) -> None:
        size = len(msg.data)
        if self.max_bytes is not None and size > self.max_bytes:
            self._drop(f"a blob of {size} bytes is over the {self.max_bytes} a value may hold")
            return
        data = msg.data  # the message's own bytes (array.array): kept as they are, not copied
        if not isinstance(data, array.array):
            data = array.array("B", data)
        if not self.cache.put(msg.digest, data):
            self._drop(f"a blob's bytes do not hash to its digest {msg.digest[:80]!r}")
            return
        self.on_blob(msg.digest)

    def _drop(self, why: str) -> None:
        self.dropped += 1
        self.node.get_logger().warning(f"dropped {why}", throttle_duration_sec=5.0)
