"""The server's request topics (ROS plumbing for ``protocol/identity.py``): the shared
``dsr/transactions`` and one ``dsr/transactions/<node name>`` per agent, found as agents appear.
Each batch of requests taken from a topic comes with the verdict on who sent it, from the ROS
graph's list of that topic's publishers (asked again whenever their number changes, and at
least every ``RECHECK`` seconds). Each agent's presence topic, ``dsr/presence/<node name>``, is
watched for its publisher's DDS liveliness (``protocol/presence.py``), counted as its request
topic's: ``on_presence`` is called when it changes."""

from __future__ import annotations

import time
from collections.abc import Callable

from rclpy.event_handler import SubscriptionEventCallbacks
from std_msgs.msg import Empty, String

from dsr_graph.protocol.identity import Publisher, Sender, sender_on
from dsr_graph.protocol.presence import Presence
from dsr_graph.protocol.topic_names import PRESENCE, TRANSACTIONS
from dsr_graph.ros.qos import qos_presence, qos_stream
from dsr_graph.ros.string_wire import cdr_utf8

MAX_BATCH = 256  # requests taken at once from one topic (handled in one turn)
RECHECK = 0.5  # seconds a verdict on a topic's publishers is trusted while their number holds
# seconds requests wait while the bytes of binary values they reference are on their way (a
# pending verdict on the sender says itself how long it may be waited for)
HOLD = 3.0
STRING = "std_msgs/msg/String"

Batch = Callable[[list[str], Sender, str], None]  # (request texts, sender verdict, topic)
NO_VERDICT = Sender(None, "the ROS graph is not asked: requests must be signed")


class RequestTopics:
    def __init__(
        self,
        node,
        on_batch: Batch,
        on_presence: Callable[[], None] = lambda: None,
        trust_graph: bool = True,
        ready: Callable[[str], bool] = lambda text: True,
    ):
        self.node = node
        self.ready = ready  # False: the request waits for what it needs (its binary values)
        self.trust_graph = trust_graph  # False: requests are signed, no verdict is waited for
        self.signers: dict[str, str] = {}  # topic -> the agent whose signed requests came on it
        self.on_batch = on_batch
        self.presence = Presence()
        self.on_presence = on_presence
        self.shared = node.resolve_topic_name(TRANSACTIONS)
        self.prefix = self.shared + "/"
        self.presence_prefix = node.resolve_topic_name(PRESENCE) + "/"
        self._subs: dict[str, tuple[object, str | None]] = {}  # topic -> (subscription, owner)
        self._verdicts: dict[str, tuple[int, float, Sender]] = {}
        self._ignored: set[str] = set()
        self._held: dict[str, tuple[float, list[str]]] = {}  # topic -> (since, texts)
        self._subscribe(self.shared, None)  # the agents' own topics: discover, as they appear
        # armed only while requests are held: no wake-up 20 times a second for nothing
        self._release_timer = node.create_timer(0.05, self.release_held)
        self._release_timer.cancel()

    @property
    def topics(self) -> list[str]:
        return sorted(self._subs)

    def discover(self, topics: list[tuple[str, list[str]]]) -> None:
        """Subscribe to the request topics of agents that appeared, among ``topics`` (the ROS
        graph's names and types; the server looks once for these and its blob topics)."""
        for topic, types in topics:
            if not topic.startswith(self.prefix) or topic in self._subs or topic in self._ignored:
                continue
            owner = topic[len(self.prefix) :]
            if "/" in owner or types != [STRING]:
                self._ignored.add(topic)
                self.node.get_logger().warning(
                    f"ignoring {topic} [{', '.join(types)}]: a request topic is "
                    f"{self.prefix}<node name> of type {STRING}"
                )
                continue
            self._subscribe(topic, owner)

    def _subscribe(self, topic: str, owner: str | None) -> None:
        # raw: the request's bytes as DDS carried them, no Python message built for each
        sub = self.node.create_subscription(
            String, topic, lambda raw, t=topic: self._on_message(t, raw), qos_stream(), raw=True
        )
        self._subs[topic] = (sub, owner)
        if owner is not None:
            self.node.create_subscription(
                Empty,
                self.presence_prefix + owner,
                lambda msg: None,  # its one message only asserts liveliness
                qos_presence(),
                # Its liveliness only: a publisher offering no lease does not match the watch,
                # and needs not, so no warning of an incompatible QoS; and rclpy's default
                # handlers would be two more entities in every wait of the executor, per agent
                # (DsrNode.create_publisher).
                event_callbacks=SubscriptionEventCallbacks(
                    liveliness=lambda info, t=topic: self._on_liveliness(t, info),
                    use_default_callbacks=False,
                ),
            )

    def _on_liveliness(self, topic: str, info) -> None:
        owner = self._subs[topic][1]
        agent = self.signers.get(topic) or self.sender(topic).agent or f"/{owner}"
        self.presence.observe(topic, agent, info.alive_count, info.not_alive_count)
        self._verdicts.pop(topic, None)  # a verdict may rest on who is alive (identity.py)
        self.on_presence()

    def _on_message(self, topic: str, raw: bytes) -> None:
        # One batch: the requests already waiting on this topic go with this one.
        sub = self._subs[topic][0]
        texts = [_text(raw)]
        with sub.handle:
            while len(texts) < MAX_BATCH:
                taken = sub.handle.take_message(String, True)
                if taken is None:
                    break
                texts.append(_text(taken[0]))
        if topic in self._held:  # keep their order behind those already waiting
            self._held[topic][1].extend(texts)
            return
        self._deliver(topic, texts, time.monotonic())

    def _deliver(self, topic: str, texts: list[str], since: float) -> None:
        waited = time.monotonic() - since
        if waited < HOLD and not all(self.ready(text) for text in texts):
            self._hold(topic, since, texts)
            return
        verdict = self.sender(topic) if self.trust_graph else NO_VERDICT
        if waited < verdict.pending:
            self._hold(topic, since, texts)
            return
        self._held.pop(topic, None)
        self.on_batch(texts, verdict, topic)

    def _hold(self, topic: str, since: float, texts: list[str]) -> None:
        self._held[topic] = (since, texts)
        if self._release_timer.is_canceled():
            self._release_timer.reset()

    def release_held(self) -> None:
        """Held requests whose wait is over go on (called as what they wait for arrives, and
        every 50 ms while some are held)."""
        for topic, (since, texts) in list(self._held.items()):
            self._deliver(topic, texts, since)
        if not self._held:
            self._release_timer.cancel()

    def owner_of(self, topic: str) -> str | None:
        """The node name a per-agent request topic belongs to (None: the shared topic)."""
        return self._subs[topic][1]

    def strangers(self, topic: str) -> tuple[str, ...]:
        """The nodes the ROS graph shows publishing on ``topic`` that are not its owner (for an
        alarm: a hint, not a proof)."""
        owner = self.owner_of(topic)
        return tuple(
            sorted(
                {
                    f"{info.node_namespace.rstrip('/')}/{info.node_name}"
                    for info in self.node.get_publishers_info_by_topic(topic)
                    if info.node_name != owner
                }
            )
        )

    def sender(self, topic: str) -> Sender:
        sub, owner = self._subs[topic]
        count = sub.get_publisher_count()
        now = time.monotonic()
        cached = self._verdicts.get(topic)
        if cached is not None and cached[0] == count and now - cached[1] < RECHECK:
            return cached[2]
        publishers = [
            Publisher(info.node_namespace, info.node_name, bytes(info.endpoint_gid[:12]))
            for info in self.node.get_publishers_info_by_topic(topic)
        ]
        verdict = sender_on(topic, owner, publishers, self.presence.liveliness(topic), count)
        if not verdict.pending:
            self._verdicts[topic] = (count, now, verdict)
        return verdict


def _text(raw: bytes) -> str:
    """A request's text; bytes that are not UTF-8 stay as they are (surrogates), for the server's
    JSON reader to refuse by name, and a message that is no String at all becomes ""."""
    try:
        return cdr_utf8(raw).decode("utf-8", "surrogateescape")
    except ValueError:
        return ""
