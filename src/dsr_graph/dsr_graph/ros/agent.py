"""The agent side of the DSR over ROS 2: an exact replica of the graph kept in a node, and a way
to send transactions and hear whether they were accepted.

    agent = DsrAgent()
    agent.setup(node, timeout_sec=10)          # topics, services, first snapshot requested
    agent.add_listener(lambda deltas, resynced: ...)
    agent.send({"ops": [...]}, on_done=lambda result: ...)

Two-phase construction: ``__init__`` builds pure state, ``setup`` attaches to a node and fails
with ``TimedOutError`` if the server does not answer. Callbacks run in the node's executor.

Subscriptions: dsr/deltas, dsr/rejections, dsr/heartbeat, dsr/durable (a verdict waits until its
change is durable), and with ``blobs=True`` dsr/blobs and
every agent's dsr/blobs/<node name> and dsr/sensor_blobs/<node name> (found as they appear,
every 0.2 s): the bytes of a value an agent sent come from the agent itself, the server's own (a
snapshot's) on dsr/blobs.
Publishers: dsr/transactions/<node name> (protocol/identity.py), dsr/presence/<node name>
(its DDS liveliness tells the server this agent is in reach; one empty message each time a
server's watch matches it, so that the server counts it alive at once),
dsr/blobs/<node name> (the bytes of the large binary values its requests reference,
protocol/blobs.py),
dsr/sensor_blobs/<node name> (those of sensor data: straight to the replicas, never the
server), dsr/alarms (a message the server did not sign, at most one per topic every 5 s).
Services: dsr/get_blob/<node name> (a binary value's bytes from this replica: the sensor data
this agent wrote, which only it holds).

With DSR_KEYSTORE (protocol/security.py) the agent signs its requests with its node's key, and
reads the deltas, rejections, heartbeats, durability notices and snapshots only when the server's
key signed them: under enforce anything else is dropped (logged, alarmed), under permissive only
logged.
Clients: dsr/get_snapshot.

The protocol itself (the replica, resends, duplicates, deltas held for their bytes, resyncs) is
``protocol/agent_core.py``, the same the in-process LocalAgent runs; this module is its ROS link,
the signatures and the agent info node.

Every agent describes itself in the graph (model/agent_info.py): its agent info node, named after
its node, says who it is and its state, ``starting`` until its replica is in sync, both directions
and its presence topic are matched and every topic it ``listens_to`` has a publisher, then
``ready``. It is written again whenever the graph says otherwise (a server restarted from an older
state, a gone mark while the agent lives). Whether it is alive the server knows (presence, the ROS
graph): no heartbeat is written. Tools that only read or send one request (the recorder, the
monitor, ``dsr apply``, ``clarc start``) pass ``describe=False``.
"""

from __future__ import annotations

import json
import math
import os
import socket
import time
import uuid
from typing import Any

import rclpy
from std_msgs.msg import Empty, String

from dsr_graph.exceptions import TimedOutError
from dsr_graph.formats.dsr_json import COLUMNS
from dsr_graph.model import agent_info
from dsr_graph.model.vocabulary import Vocabulary
from dsr_graph.protocol import topic_names
from dsr_graph.protocol.agent_core import (
    AGENT_BLOB_BYTES,
    IDLE_TICK,
    SERVER_SILENCE,
    TICK,
    AgentCore,
    Listener,
    Verdict,
)
from dsr_graph.protocol.blobs import sensor_refs_in_text
from dsr_graph.protocol.cut_off import CUT_OFF_AFTER, CutOffWatch
from dsr_graph.protocol.identity import NODE_NOT_KNOWN, agent_topic, presence_topic
from dsr_graph.protocol.security import Security
from dsr_graph.protocol.server_core import Result
from dsr_graph.ros import process_gc
from dsr_graph.ros.blob_service import blob_answer
from dsr_graph.ros.blob_topics import BlobInbox, blob_message
from dsr_graph.ros.dsr_node import CUT_OFF
from dsr_graph.ros.exit_timer import exit_now
from dsr_graph.ros.log_levels import log_at
from dsr_graph.ros.qos import qos_blobs, qos_latched, qos_presence, qos_stream
from dsr_graph.ros.server_probe import ServerProbe
from dsr_msgs.msg import Blob
from dsr_msgs.srv import GetBlob, GetSnapshot

__all__ = ["SERVER_SILENCE", "DsrAgent"]

BLOB_DISCOVERY_PERIOD = 0.2  # seconds between looks for agents' dsr/blobs/<node name> (blobs=True)
DESCRIBE_PERIOD = 0.25  # seconds between looks at whether the agent info node is as it should be
# after a refusal (a program with no key of its own under an enforcing server, a policy without
# its info node): the next try, and its warning, this much later, not four times a second
DESCRIBE_REFUSED = 10.0
ANNOUNCE_EVERY = 5.0  # seconds between two sends of rmw's node list (_announce_node)
# seconds after such a send within which a refusal for an unknown node may still have crossed it
ANNOUNCE_GRACE = 3.0


class DsrAgent:
    def __init__(
        self, vocabulary: Vocabulary | None = None, blobs: bool = False, describe: bool = True
    ):
        """``blobs``: receive the bytes of large binary values (camera images) as they change;
        without, the replica holds such a value as a ``BlobRef`` (its digest, type and shape).
        ``describe``: keep an agent info node in the graph (the module's docstring)."""
        self._run = uuid.uuid4().hex[:6]
        # the protocol (protocol/agent_core.py); this object is its link to ROS
        self.core = AgentCore("", self, self._run, vocabulary=vocabulary, blobs=blobs)
        self.describes = describe
        self.listens_to: list[str] = []  # topics that need a publisher before it is ready
        self.can_do: list[str] = []
        self._started_at = time.time()
        # the process's own: asked once, not at every look at the info node
        self._process = {"pid": os.getpid(), "host": socket.gethostname()}
        self._described = 0.0  # the last look at its info node, time.monotonic()
        self._describing = False  # an info write is on its way
        self._tick_timer = None  # the transport's timer, set up with the node (``_pace``)
        self._ticking_every = TICK
        self.node = None
        self.name = ""
        self._snapshot_future = None
        self.security = Security()
        self.forged = 0  # messages dropped because the server did not sign them
        self._cut_off = CutOffWatch()  # the middleware's link to the server (protocol/cut_off.py)
        self._probe: ServerProbe | None = None
        self._announced = -math.inf  # when the node list was last sent again (_announce_node)
        self._presence_readers = 0  # the servers' presence watches it has said it is alive to

    # ------------------------------------------------------------------ set-up
    def setup(self, node, timeout_sec: float = 10.0) -> None:
        self.node = node
        self.name = self.core.name = node.get_fully_qualified_name()
        self.security = Security.from_environment(self.name)
        if self.security.checks and self.security.signer is None:
            node.get_logger().warning(
                f"{self.security.mode}: the keystore {self.security.keystore.root} has no key "
                f"for {self.name}, so the DSR server will refuse its requests (read-only; "
                f"dsr keystore add {self.security.keystore.root} {self.name})"
            )
        self._alarm_pub = node.create_publisher(String, topic_names.ALARMS, qos_stream())
        # a request topic of our own: the server knows who we are from the ROS graph
        self._tx_pub = node.create_publisher(String, agent_topic(node.get_name()), qos_stream())
        # its liveliness tells the server this agent is in reach (_say_present)
        self._presence_pub = node.create_publisher(
            Empty, presence_topic(node.get_name()), qos_presence()
        )
        self._blob_pub = node.create_publisher(
            Blob, f"{topic_names.BLOBS}/{node.get_name()}", qos_blobs()
        )
        # sensor data's bytes go one hop, to the replicas that want them, never the server; a
        # reader that did not get them asks this agent, which alone holds them
        self._sensor_blob_pub = node.create_publisher(
            Blob, f"{topic_names.SENSOR_BLOBS}/{node.get_name()}", qos_blobs()
        )
        node.create_service(GetBlob, f"{topic_names.GET_BLOB}/{node.get_name()}", self._on_get_blob)
        if self.core.wants_blobs:  # subscribed before the deltas: a blob is taken before its delta
            # any node may publish on a dsr/blobs/<name>: bytes count only under their digest,
            # and no blob larger than all this replica keeps is taken
            self._blob_inbox = BlobInbox(
                node,
                self.core.blobs,
                on_blob=lambda d: self.core.blob_arrived(time.monotonic()),
                max_bytes=AGENT_BLOB_BYTES,
            )
            self._blob_inbox.listen(topic_names.BLOBS)
            self._listen_to_agents()
            node.create_timer(BLOB_DISCOVERY_PERIOD, self._listen_to_agents)
        self._delta_sub = node.create_subscription(
            String, topic_names.DELTAS, self._on_delta, qos_stream()
        )
        node.create_subscription(String, topic_names.REJECTIONS, self._on_rejection, qos_stream())
        node.create_subscription(String, topic_names.HEARTBEAT, self._on_heartbeat, qos_latched())
        node.create_subscription(String, topic_names.DURABLE, self._on_durable, qos_stream())
        self._snapshot_client = node.create_client(GetSnapshot, topic_names.GET_SNAPSHOT)
        if not self._snapshot_client.wait_for_service(timeout_sec=timeout_sec):
            raise TimedOutError(
                f"no DSR server answered on {topic_names.GET_SNAPSHOT} within {timeout_sec} s "
                "(is dsr_server running with the same ROS_DOMAIN_ID?)"
            )
        # the replica is most of this process after each snapshot (ros/process_gc.py)
        self.core.add_listener(lambda deltas, resynced: resynced and process_gc.settle())
        self._tick_timer = node.create_timer(TICK, self._tick)
        self.core.ask_snapshot(time.monotonic())

    def describe(self, can_do: list[str] = (), listens_to: list[str] = ()) -> None:
        """What this agent does for the others, and the topics it needs a publisher on before it
        is ready (its devices: a microphone's, a touch screen's)."""
        self.can_do = sorted(set(can_do))
        self.listens_to = sorted(set(listens_to))

    @property
    def state(self) -> str:
        """``ready`` once in sync, matched both ways and hearing every topic it listens to."""
        inputs = all(self.node.count_publishers(t) > 0 for t in self._inputs())
        return agent_info.READY if self.ready and inputs else agent_info.STARTING

    def _inputs(self) -> list[str]:
        """The topics it listens to, as remapped and namespaced for this node."""
        return [self.node.resolve_topic_name(t) for t in self.listens_to]

    def _describe_self(self, now: float) -> None:
        """Write the agent info node where the replica shows it is not as it should be."""
        if now - self._described < DESCRIBE_PERIOD or self._describing or not self.synced:
            return
        self._described = now
        attrs = {
            "state": self.state,
            **self._process,
            "agent_run": self._run,
            "listens_to": self._inputs(),
            "can_do": self.can_do,
            "started_at": self._started_at,
        }
        ops = agent_info.info_ops(self.graph, self.name, attrs)
        if ops:
            self._describing = True
            self.send({"ops": ops}, on_done=self._described_done)

    def _described_done(self, result: Result) -> None:
        self._describing = False
        if not result.accepted:
            self._described = time.monotonic() + DESCRIBE_REFUSED - DESCRIBE_PERIOD
            self.node.get_logger().warning(
                f"could not describe this agent (tried again in {DESCRIBE_REFUSED:g} s): "
                f"{result.error}"
            )

    def _listen_to_agents(self) -> None:
        self._blob_inbox.listen_to_agents(
            self.node.get_topic_names_and_types(), (topic_names.BLOBS, topic_names.SENSOR_BLOBS)
        )

    def add_listener(self, listener: Listener) -> None:
        self.core.add_listener(listener)

    # ------------------------------------------------------------------ what the core knows
    @property
    def replica(self):
        return self.core.replica

    @property
    def graph(self):
        return self.core.replica.graph

    @property
    def boot(self) -> str:
        """The start of the server last heard (new at each restart; "" before its heartbeat)."""
        return self.core.boot

    @property
    def heard(self) -> float | None:
        """When the server's heartbeat was last heard (time.monotonic()), None before."""
        return self.core.heard

    @property
    def server_gap(self) -> tuple[float, float]:
        """The last silence of the server's heartbeat (time.monotonic()): its last beat before,
        its first after."""
        return self.core.server_gap

    @property
    def out_of_reach(self) -> frozenset[str]:
        """The agents the server cannot hear now (its heartbeat)."""
        return self.core.out_of_reach

    @property
    def reach_losses(self) -> int:
        return self.core.reach_losses

    @property
    def resyncs(self) -> int:
        """Snapshots loaded, the first included (bench/counter.py reports the others)."""
        return self.core.resyncs

    @property
    def synced(self) -> bool:
        """A snapshot has been loaded (the graph is the server's, as of some seq)."""
        return self.core.synced

    @property
    def ready(self) -> bool:
        """Synced with the server, and both directions matched: requests reach the server and
        its deltas reach us (before that, a delta would only be recovered by a resync); and the
        server counts it alive (``_say_present``)."""
        return self.synced and self._link_matched() and self._presence_readers > 0

    # ------------------------------------------------------------------ sending
    def next_id(self) -> str:
        return self.core.next_id()

    def send(self, doc: dict[str, Any], on_done: Verdict | None = None) -> str:
        """Queue a transaction (agent and id are filled in); ``on_done`` gets its ``Result``."""
        ident = self.core.send(doc, on_done, time.monotonic(), sign=self._sign)
        self._pace()
        return ident

    def _sign(self, text: str) -> str:
        return self.security.sign(topic_names.TRANSACTIONS, text)

    # ------------------------------------------------------------------ the core's link
    def publish(self, text: str, blobs: dict[str, bytes]) -> None:
        sensor = sensor_refs_in_text(text) if blobs else set()
        for digest, data in blobs.items():  # the bytes first: the server holds for them
            publisher = self._sensor_blob_pub if digest in sensor else self._blob_pub
            publisher.publish(blob_message(digest, data))
        self._tx_pub.publish(String(data=text))

    def _on_get_blob(self, request: GetBlob.Request, response: GetBlob.Response):
        """The bytes of a binary value as this agent's replica holds it (the sensor data it
        wrote: no one else holds them)."""
        return blob_answer(self.core.graph, request, response, self.core.replica.seq)

    def matched(self) -> bool:
        return self._tx_pub.get_subscription_count() > 0  # one rcl query a send

    def ask_snapshot(self) -> None:
        # column by column: the elements it does not use are never parsed (dsr_json.to_columns)
        future = self._snapshot_client.call_async(GetSnapshot.Request(layout=COLUMNS))
        self._snapshot_future = future
        future.add_done_callback(self._on_snapshot)

    def withdraw_snapshot(self) -> None:
        if self._snapshot_future is not None:
            self._snapshot_client.remove_pending_request(self._snapshot_future)
            self._snapshot_future = None

    def log(self, level: str, message: str) -> None:
        log_at(self.node.get_logger(), level, message)

    # ------------------------------------------------------------------ receiving
    def _from_server(self, channel: str, text: str) -> str | None:
        """The text of a message the server signed (or any, with security off); None: drop it."""
        opened, problem = self.security.from_server(channel, text)
        if problem:
            self._forged_message(channel, problem, dropped=opened is None)
        return opened

    def _forged_message(self, channel: str, problem: str, dropped: bool) -> None:
        self.forged += dropped
        if not self.security.should_alarm((channel, problem), time.monotonic()):
            return
        verdict = "dropped" if dropped else "taken (permissive)"
        self.node.get_logger().error(f"a message the DSR server did not sign, {verdict}: {problem}")
        alarm = {"kind": "signature", "topic": channel, "node": self.name, "message": problem}
        self._alarm_pub.publish(
            String(data=self.security.sign(topic_names.ALARMS, json.dumps(alarm)))
        )

    def _on_delta(self, msg: String) -> None:
        text = self._from_server(topic_names.DELTAS, msg.data)
        if text is not None:
            self.core.on_delta(text, time.monotonic())
            self._pace()

    def _on_rejection(self, msg: String) -> None:
        text = self._from_server(topic_names.REJECTIONS, msg.data)
        # every agent hears every refusal: ours names our topic, and /speech's not /speech2's
        if text is not None and f"{self._tx_pub.topic_name} {NODE_NOT_KNOWN}" in text:
            self._not_known(time.monotonic())
        if text is not None:
            self.core.on_rejection(text, time.monotonic())
            self._pace()

    def _on_heartbeat(self, msg: String) -> None:
        # a forged heartbeat must not make a dead server look alive
        text = self._from_server(topic_names.HEARTBEAT, msg.data)
        if text is not None:
            self.core.on_heartbeat(text, time.monotonic())
            self._pace()

    def _on_durable(self, msg: String) -> None:
        # a forged notice must not make a change look durable: the server's signature only
        text = self._from_server(topic_names.DURABLE, msg.data)
        if text is not None:
            self.core.on_durable(text, time.monotonic())
            self._pace()

    def _on_snapshot(self, future) -> None:
        if future is not self._snapshot_future:
            return  # an answer to a request already given up on
        self._snapshot_future = None
        try:
            response = future.result()
        except Exception as e:  # a failed call: the tick asks again
            self.core.snapshot_failed(repr(e))
            return
        text = self._from_server(topic_names.GET_SNAPSHOT, response.snapshot_json)
        if text is None:
            self.core.snapshot_failed("not signed by the server")
            return
        self.core.on_snapshot(text, time.monotonic())
        self._pace()

    def _tick(self) -> None:
        now = time.monotonic()
        self._say_present()
        self.core.tick(now)
        if self.describes:
            self._describe_self(now)
        self._watch_link(now)
        self._pace()

    # ------------------------------------------------------------------ the middleware's link
    def _say_present(self) -> None:
        """One empty message on the presence topic each time a server's watch matches it: a
        reader counts an AUTOMATIC writer alive only at its middleware's first assertion, 2/3 of
        the lease after the match, and a sample asserts it at once. Until then the server could
        not tell this agent's end by liveliness: killed within that time and respawned at once,
        it read gone only when DDS dropped its participant (over 5 s in a CI run)."""
        readers = self._presence_pub.get_subscription_count()
        if readers > self._presence_readers:
            self._presence_pub.publish(Empty())
        self._presence_readers = readers

    def _watch_link(self, now: float) -> None:
        """An agent its own participant cut off from the server ends, to be restarted
        (protocol/cut_off.py); the probe runs in a process of its own, asked each tick."""
        if self._probe is not None:
            seen = self._probe.answer()
            if seen is not None:
                self._probe = None
                if self._cut_off.probed(seen, self._link_matched()):
                    self._cut_off_found()
            return
        if self._cut_off.due_look(now) and self._cut_off.look(self._link_matched(), now):
            self._probe = ServerProbe(
                self.node.context.get_domain_id(),
                self._delta_sub.topic_name,
                self._tx_pub.topic_name,
            )

    def _announce_node(self, now: float, why: str) -> None:
        """Send rmw's node list again, for a server whose ROS graph does not name our node. Seen
        after a server stalled beyond the DDS lease (SIGSTOP for 4 s): its participant found
        ours again but not rmw's node names of it (ros_discovery_info), and refused our requests
        for as long as it was watched (40 s). rmw sends that list when a node of the context
        comes or goes: a node made and destroyed at once (no rosout, no parameter services).
        It made the server know the name in 1 of the 6 runs where it was tried."""
        if now - self._announced < ANNOUNCE_EVERY:
            return
        self._announced = now
        herald = rclpy.create_node(
            f"{self.node.get_name()}_announce",
            namespace=self.node.get_namespace(),
            context=self.node.context,
            enable_rosout=False,
            start_parameter_services=False,
        )
        herald.destroy_node()
        self.node.get_logger().info(f"sent rmw's node list again ({why})")

    def _link_matched(self) -> bool:
        return (
            self._delta_sub.get_publisher_count() > 0 and self._tx_pub.get_subscription_count() > 0
        )

    def _not_known(self, now: float) -> None:
        """The server refused a request of ours: its ROS graph does not name our node. rmw's node
        list is sent again; if it was sent long enough before this refusal and did not reach the
        server either (after a stall: 5 runs of test_server_stall.py in 10), the link is as
        broken as an unmatched one."""
        if now - self._announced < ANNOUNCE_GRACE or self._announced == -math.inf:
            self._announce_node(
                now, "the server refused a request: it did not know this node's name"
            )
            return
        self._cut_off_found(
            f"the server still does not know this node's name {now - self._announced:.0f} s "
            "after rmw's node list was sent again"
        )

    def _cut_off_found(self, why: str = "") -> None:
        why = why or (
            f"a participant made afresh sees the server, this node's has not matched it for "
            f"{CUT_OFF_AFTER:g} s or more"
        )
        message = (
            f"cut off from the DSR server by the middleware: {why} (Fast DDS did not find it "
            "again after a stall, or found it only in part)"
        )
        if getattr(self.node, "stops", None) is not None:  # run_node's: its launch restarts it
            self.node.get_logger().fatal(f"{message}; exiting to be restarted")
            exit_now(CUT_OFF)
        self.node.get_logger().error(message)

    def _pace(self) -> None:
        """Tick every ``TICK`` while the core waits on something (a verdict, a delta, a
        snapshot), every ``IDLE_TICK`` otherwise: each wake-up costs the process about 0.2 ms,
        and an idle agent's 20 a second were most of its CPU."""
        first_look = self.describes and not self._described  # readiness is not kept waiting
        every = TICK if self.core.busy or first_look else IDLE_TICK
        if self._tick_timer is None or every == self._ticking_every:
            return
        self._ticking_every = every
        self._tick_timer.timer_period_ns = int(every * 1e9)
        if every == TICK:
            self._tick_timer.reset()  # from now: the next tick is TICK away, not IDLE_TICK
