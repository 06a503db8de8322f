"""The DSR server node: the one authoritative graph (ROS plumbing around ``server_core``).

ROS Parameters:
    world_file (str): world to start from (ours or CORTEX) when state_dir holds no state yet;
        a state_dir holding a graph made from another world is refused unless ``resume``.
    resume (bool): go on with the graph in state_dir even if it was made from another world.
    vocabulary_file (str): vocabulary file; empty for the built-in one.
    state_dir (str): where the state persists (default $XDG_STATE_HOME/dsr/<node name>);
        a second server on the same directory, or a corrupt one, exits 1 naming it.
    compact_every (int): journaled deltas between snapshots (default 1000).
    commit_delay (float): seconds a group commit waits for more changes before its fdatasync
        (default 0: it syncs what has gathered at once, while the server goes on accepting).
    max_request_bytes (int): requests of more UTF-8 bytes are rejected (default 4 MiB).
    max_ops (int): transactions of more operations are rejected (default 10000).
    max_nodes (int): a transaction that would grow the graph beyond it is rejected (1000000).
    max_lease (float): longest claim lease in seconds; a longer one is rejected (default 300).
    max_value_bytes (int): a binary value (bytes, an image) of more bytes is rejected (8 MiB).
    publish_poses (bool): publish a PoseStamped per geometric node (default true).
    markers_period (float): seconds between checks for a changed graph to draw on dsr/markers
        (default 1.0; 0: no markers). Graphs above 1000 nodes are not drawn.
    heartbeat_period (float): seconds between heartbeats and claim housekeeping (default 1.0).
    agent_grace (float): seconds a claim holder may be missing from the ROS graph before its
        claims are freed (default 3.0). An agent's info node (model/agent_info.py) is marked
        gone at once when it goes out of reach, and after 2 s missing from the ROS graph (not in
        the server's first 3 s); an agent that is alive undoes a wrong mark.
    rt_history_seconds (float), rt_history_count (int): each RT edge's past transforms kept for
        dsr/get_transform's ``at`` (default 10 s, at most 100 values; model/rt_history.py).
    policy_file (str): YAML of who may write what, with which claim priority
        (model/policy.py); empty: every agent may write anything, all with the same priority.
Subscriptions:
    dsr/transactions/<node name> (std_msgs/String): each agent's JSON transaction requests,
        taken as that node's only while the ROS graph shows it as the topic's only publisher
        (protocol/identity.py); the delta's "agent" is that node's fully qualified name.
    dsr/transactions (std_msgs/String): the shared topic of earlier versions, attributed only
        while exactly one node publishes on it; otherwise each request gets a rejection.
    dsr/presence/<node name> (std_msgs/Empty): one message when the watch matches; its
        publisher's DDS liveliness (1 s lease) tells whether that agent is in reach
        (protocol/presence.py).
    dsr/blobs/<node name> (dsr_msgs/Blob): the bytes of the binary values an agent's requests
        reference (protocol/blobs.py), but sensor data's: those go one hop, from the agent's
        dsr/sensor_blobs/<node name> to the replicas; the server keeps their reference.
Publishers:
    dsr/blobs (dsr_msgs/Blob): bytes no agent sent, before the delta or snapshot that needs them
        (a snapshot's; the bytes of an agent's values went out on its dsr/blobs/<node name>).
    dsr/deltas (std_msgs/String): accepted deltas, one per transaction, in seq order (a
        volatile one, sensor data, carries the seq it follows: protocol/volatility.py), each
        broadcast before it is durable, with the server's ``boot`` and the ``durable`` seq.
    dsr/durable (std_msgs/String): {boot, durable} after each group commit: every delta up to
        seq ``durable`` is on disk (a writer's verdict waits for it: protocol/acceptance.py).
    dsr/rejections (std_msgs/String): {id, agent, reason, error} for each refused request.
    dsr/alarms (std_msgs/String): {kind, topic, intruders, message} when a request topic has a
        publisher that is not its owner (at most one per topic and intruders every 5 s).
    dsr/heartbeat (std_msgs/String, latched): {seq, stamp, boot, durable, unreachable} (boot:
        new at each start; unreachable: agents listed in the ROS graph whose presence topic's DDS
        liveliness lapsed, protocol/presence.py; also sent at once when that list changes).
    /tf, /tf_static (tf2_msgs/TFMessage): the RT tree for tf2 listeners, in metres, frame ids =
        node names; edges unchanged since the start on /tf_static (protocol/tf_frames.py);
        /tf is volatile, so nothing is sent on it while nobody subscribes.
    dsr/markers (visualization_msgs/MarkerArray, latched): the graph drawn for RViz and
        Foxglove, in the RT root's frame, in metres (protocol/graph_markers.py); drawn only
        while someone subscribes (a new subscriber may get the last drawing first).
    dsr/pose/<node> (geometry_msgs/PoseStamped, latched): each geometric node's pose in its
        RT parent's frame (header.frame_id = the parent's name), again on every change.
Services:
    dsr/get_attribute (dsr_msgs/GetAttribute), dsr/get_node (dsr_msgs/GetNode),
    dsr/get_snapshot (dsr_msgs/GetSnapshot: the document, or column by column for a replica),
    dsr/get_transform (dsr_msgs/GetTransform: now, or
    at a past time from the RT history), dsr/get_blob (dsr_msgs/GetBlob: a binary value's
    bytes, for a replica that holds only its digest; for sensor data, where they are).
"""

from __future__ import annotations

import os
import time
import uuid
from typing import Any

from geometry_msgs.msg import PoseStamped
from std_msgs.msg import String
from visualization_msgs.msg import MarkerArray

from dsr_graph.exceptions import KeystoreError, LookupFailed
from dsr_graph.formats import dsr_json
from dsr_graph.formats.default_paths import state_path
from dsr_graph.formats.group_commit import GroupCommit
from dsr_graph.formats.state_store import StateStore
from dsr_graph.model import rigid
from dsr_graph.model.agent_info import GONE
from dsr_graph.model.agent_info import states as agent_states
from dsr_graph.model.binary import compact, dumps
from dsr_graph.model.policy import OPEN, Policy
from dsr_graph.model.vocabulary import RT, Vocabulary
from dsr_graph.protocol import queries, topic_names
from dsr_graph.protocol.absence import Absences
from dsr_graph.protocol.acceptance import broadcast_then_commit, outgoing
from dsr_graph.protocol.attribution import attribute
from dsr_graph.protocol.blobs import BlobCache, held_refs_in_text
from dsr_graph.protocol.graph_markers import drawing
from dsr_graph.protocol.identity import Sender
from dsr_graph.protocol.security import ENFORCE, OFF, Security
from dsr_graph.protocol.server_core import Rejection, ServerCore
from dsr_graph.protocol.snapshot_text import LAYOUTS, snapshot_text
from dsr_graph.protocol.state_boot import boot_state
from dsr_graph.protocol.tf_frames import moved_nodes, transform_of
from dsr_graph.ros.blob_service import blob_answer
from dsr_graph.ros.blob_topics import BlobInbox, blob_message
from dsr_graph.ros.dsr_node import DsrNode, main_for
from dsr_graph.ros.log_levels import log_at
from dsr_graph.ros.marker_messages import marker_array
from dsr_graph.ros.parameters import float_param, param
from dsr_graph.ros.qos import qos_blobs, qos_latched, qos_stream
from dsr_graph.ros.request_topics import RequestTopics
from dsr_graph.ros.server_parameters import declare_server_parameters, limits
from dsr_graph.ros.string_wire import string_cdr
from dsr_graph.ros.tf_publisher import TfPublisher
from dsr_msgs.msg import Blob
from dsr_msgs.srv import GetAttribute, GetBlob, GetNode, GetSnapshot, GetTransform

ALARM_EVERY = 5.0  # seconds between alarms about the same intruders on the same topic
BLOB_CACHE_BYTES = 256 * 1024 * 1024  # binary values' bytes the server keeps, newest first
MAX_DRAWN_NODES = 1000  # a larger graph is not drawn on dsr/markers (unreadable, and costly)
DISCOVERY_PERIOD = 0.2  # seconds between looks at the ROS graph for agents that appeared
INFO_GRACE = 2.0  # seconds an agent described in the graph may be missing before it is gone
DISCOVERY = 3.0  # seconds after the server's start before anyone is marked gone


class DsrServer(DsrNode):
    NAME = "dsr_server"

    @classmethod
    def declare_node_parameters(cls, node) -> None:
        declare_server_parameters(node)

    def __init__(self, node_name: str = "", **kwargs: Any):
        super().__init__(node_name, **kwargs)
        self.core: ServerCore | None = None
        self.store: StateStore | None = None
        self.journal: GroupCommit | None = None
        self._pose_pubs: dict[str, tuple[Any, PoseStamped]] = {}  # name -> publisher, message
        # layout -> (version, seq, signed text, blobs)
        self._snapshot_cache: dict[str, tuple[Any, int, str, dict]] = {}
        self._absences = Absences()
        self._started = time.monotonic()
        self._alarmed: dict[tuple, float] = {}  # (topic, kind, intruders) -> when
        # tells agents this server restarted: they re-send, and resync if they saw changes it
        # never made durable (every delta carries it)
        self._boot = uuid.uuid4().hex[:16]

    # ------------------------------------------------------------------ start
    def setup(self) -> None:
        """Load the state (or the world), then open the topics and services."""
        self.security = self._security()
        vocabulary = Vocabulary.load(param(self, "vocabulary_file"))
        policy = Policy.load(param(self, "policy_file")) if param(self, "policy_file") else OPEN
        if policy is OPEN:
            self.get_logger().warning(
                "no policy loaded (policy_file): every agent may write anything, all with the "
                "same claim priority, so no one preempts anyone"
            )
        else:
            self.get_logger().info(
                f"policy {policy.source}: {len(policy.rules)} entries "
                f"({', '.join(r.name for r in policy.rules)})"
            )
        self.store = StateStore(
            # empty (a launch file's unset argument): the default
            param(self, "state_dir") or state_path("dsr", self.get_name()),
            compact_every=param(self, "compact_every"),
        )
        self.store.open()
        boot = boot_state(
            self.store,
            param(self, "world_file"),
            vocabulary,
            policy,
            limits(self),
            resume=param(self, "resume"),
        )
        self.core = boot.core
        for level, message in boot.notes:
            log_at(self.get_logger(), level, message)
        self.core.graph.rt_history.limit(
            float_param(self, "rt_history_seconds"), param(self, "rt_history_count")
        )

        self._deltas = self.create_publisher(String, topic_names.DELTAS, qos_stream())
        self._rejections = self.create_publisher(String, topic_names.REJECTIONS, qos_stream())
        self._heartbeat = self.create_publisher(String, topic_names.HEARTBEAT, qos_latched())
        self._durable_pub = self.create_publisher(String, topic_names.DURABLE, qos_stream())
        self.journal = GroupCommit(
            self.store,
            durable=self.core.seq,  # what was replayed is synced (StateStore.replay_journal)
            on_durable=self._on_durable,
            on_failure=self._disk_failed,
            delay=float_param(self, "commit_delay"),
        )
        self.journal.start()
        self._alarms = self.create_publisher(String, topic_names.ALARMS, qos_stream())
        # large binary values travel beside the JSON (protocol/blobs.py): what the agents send,
        # kept until their requests take it, and what the deltas carry out
        self.blobs = BlobCache(BLOB_CACHE_BYTES)
        self._blob_pub = self.create_publisher(Blob, topic_names.BLOBS, qos_blobs())
        self.requests = RequestTopics(
            self,
            self.on_requests,
            on_presence=self.on_presence,
            # signed requests prove their sender: the ROS graph's word is not needed (nor held
            # for: a participant found again after a cut may come back without its name)
            trust_graph=self.security.mode != ENFORCE,
            # a request is held (a few seconds at most) until the bytes it references came
            # (sensor data's never come: their writer sends them to the replicas, one hop)
            ready=lambda text: all(d in self.blobs for d in held_refs_in_text(text)),
        )
        self.blob_inbox = BlobInbox(
            self,
            self.blobs,
            on_blob=lambda digest: self.requests.release_held(),
            max_bytes=self.core.max_value_bytes,
        )
        self.on_discover()
        self.create_timer(DISCOVERY_PERIOD, self.on_discover)
        self._publish_poses = bool(param(self, "publish_poses"))
        self._tf = TfPublisher(self, self.core.graph)
        self._markers = self.create_publisher(MarkerArray, topic_names.MARKERS, qos_latched())
        self._drawn = (-1, -1)
        if float_param(self, "markers_period") > 0:
            self.create_timer(float_param(self, "markers_period"), self.on_markers)
        self.create_service(GetAttribute, topic_names.GET_ATTRIBUTE, self.on_get_attribute)
        self.create_service(GetNode, topic_names.GET_NODE, self.on_get_node)
        self.create_service(GetSnapshot, topic_names.GET_SNAPSHOT, self.on_get_snapshot)
        self.create_service(GetTransform, topic_names.GET_TRANSFORM, self.on_get_transform)
        self.create_service(GetBlob, topic_names.GET_BLOB, self.on_get_blob)
        self.create_timer(float_param(self, "heartbeat_period"), self.on_heartbeat)
        if param(self, "publish_poses"):
            graph = self.core.graph
            self._publish_poses_of([graph.node(e.dst).name for e in graph.edges_of_type(RT)])
        self.on_heartbeat()

    def _security(self) -> Security:
        me = self.get_fully_qualified_name()
        security = Security.from_environment(me)
        if security.mode == OFF:
            self.get_logger().warning(
                "DSR security off (no DSR_KEYSTORE): any process on the ROS domain can take a "
                "stopped agent's name and publish on the DSR's topics"
            )
            return security
        if security.server != me:
            raise KeystoreError(
                f"the keystore {security.keystore.root} is for the server {security.server!r}; "
                f"this server is {me!r}"
            )
        if security.signer is None:
            raise KeystoreError(
                f"the keystore {security.keystore.root} has no key for {me}: "
                f"dsr keystore init {security.keystore.root}"
            )
        self.get_logger().info(
            f"DSR security {security.mode}: keystore {security.keystore.root}, "
            f"{len(security.verifier.keys)} keys; every message of the server signed"
        )
        return security

    def _publish(self, publisher, channel: str, doc: dict[str, Any]) -> None:
        text = compact(doc)
        publisher.publish(string_cdr(self.security.sign(channel, text)))  # encoded once

    def close(self) -> None:
        if self.journal is not None:
            try:
                self.journal.close()  # a clean stop: what was broadcast is made durable
            except OSError as e:
                self.get_logger().error(f"cannot persist to {self.store.dir} at the stop: {e}")
        if self.store is not None:
            self.store.close()

    # ------------------------------------------------------------------ transactions
    def on_requests(self, texts: list[str], sender: Sender, topic: str) -> None:
        """A batch of requests from one topic (one fdatasync covers the accepted ones)."""
        accepted = []
        for text in texts:
            try:
                agent, refusal, payload = self._attribute(text, sender, topic)
                if agent is None:
                    result = self.core.unattributed(payload, refusal)
                else:
                    result = self.core.submit(payload, sender=agent, blobs=self.blobs.get)
            except Exception as e:  # a bug must not take the server down with it
                self.get_logger().error(f"internal error on a request (state unchanged): {e!r}")
                result = None
            for delta in self.core.take_server_deltas():  # committed before the request's
                self.get_logger().info(
                    f"a new run of {delta['ops'][0]['node']} writes: the one before ended, its "
                    "info node says gone"
                )
                accepted.append(delta)
            if result is None:
                continue
            if isinstance(result, Rejection):
                self._publish(self._rejections, topic_names.REJECTIONS, result.to_json())
                self.get_logger().debug(
                    f"rejected {result.id or '?'} from {result.agent or '?'}: {result.violation}"
                )
            else:
                accepted.append(result)
        if accepted:
            self._accept(accepted)

    def _attribute(self, text: str, sender: Sender, topic: str):
        """(the agent a request is from or None, the refusal if None, the request's text):
        protocol/attribution.py's rule, with its alarms raised here."""
        owner = self.requests.owner_of(topic)
        found = attribute(
            self.security, text, sender, topic, owner, lambda: self.requests.strangers(topic)
        )
        if found.proven_signer is not None:
            self.requests.signers[topic] = found.proven_signer
        for alarm in found.alarms:
            self._alarm(topic, alarm.kind, alarm.message, alarm.intruders, alarm.refused)
        return found.agent, found.refusal, found.payload

    def _alarm(
        self, topic: str, kind: str, message: str, intruders: tuple[str, ...], refused=True
    ) -> None:
        """Logged and sent on dsr/alarms, at most every ALARM_EVERY s per topic and cause."""
        key = (topic, kind, intruders)
        now = time.monotonic()
        if now - self._alarmed.get(key, -ALARM_EVERY) < ALARM_EVERY:
            return
        self._alarmed[key] = now
        if refused:
            self.get_logger().error(f"refusing requests on {topic}: {message}")
        else:
            self.get_logger().warning(f"taking requests on {topic} (permissive): {message}")
        alarm = {"kind": kind, "topic": topic, "intruders": list(intruders), "message": message}
        self._publish(self._alarms, topic_names.ALARMS, alarm)

    def _accept(self, deltas: list[dict[str, Any]]) -> None:
        """Broadcast, durable at the next group commit (protocol/acceptance.py)."""
        if broadcast_then_commit(self.journal, deltas, self._broadcast):
            try:
                self.journal.compact(self.core.durable_snapshot())
            except OSError as e:
                self._disk_failed(e)

    def _on_durable(self, seq: int) -> None:
        """The commit thread made every delta up to ``seq`` durable: their writers may hear."""
        try:
            notice = {"boot": self._boot, "durable": seq}
            self._publish(self._durable_pub, topic_names.DURABLE, notice)
        except Exception as e:  # never ends the commit thread: the next notice or beat says it
            if self.context.ok():  # else a stop: the journal is durable all the same
                self.get_logger().error(f"could not publish on {topic_names.DURABLE}: {e!r}")

    def _disk_failed(self, error: OSError) -> None:
        """The journal cannot be written: what was broadcast since the last commit may never be
        durable, and the server cannot keep its word. It ends at once, as if killed: the state
        on disk restarts consistent, and replicas that saw the rest resync with it."""
        self.get_logger().fatal(
            f"cannot persist to {self.store.dir}: {error}; stopping (changes after seq "
            f"{self.journal.durable} were broadcast but not acknowledged: replicas resync)"
        )
        os._exit(3)

    def _broadcast(self, delta: dict[str, Any]) -> None:
        doc, blobs = outgoing(delta, self.blobs)
        for digest, data in blobs.items():  # the bytes first: a reader holds the delta
            self._blob_pub.publish(blob_message(digest, data))
        doc = {**doc, "boot": self._boot, "durable": self.journal.durable}
        self._publish(self._deltas, topic_names.DELTAS, doc)
        self._tf.on_delta(self.core.graph, delta)
        if self._publish_poses:
            self._publish_poses_of(moved_nodes(delta))

    def on_discover(self) -> None:
        """Agents that appeared: their request and blob topics, from one look at the ROS graph."""
        topics = self.get_topic_names_and_types()
        self.requests.discover(topics)
        self.blob_inbox.listen_to_agents(topics)

    # ------------------------------------------------------------------ poses
    def _publish_poses_of(self, names: list[str]) -> None:
        """Each node's pose on its dsr/pose/<node>, stamped alike. A streaming skeleton moves
        17 nodes 30 times a second: each topic's message is kept and refilled (a new message
        and clock reading per pose cost twice as much CPU)."""
        if not names:
            return
        stamp = self.get_clock().now().to_msg()
        for name in names:
            pose = transform_of(self.core.graph, name)
            if pose is None:
                continue  # deleted, or not geometric any more: its last pose stays latched
            pub, msg = self._pose_pubs.get(name) or (None, PoseStamped())
            if pub is None:
                topic = topic_names.pose_topic(name)
                pub = self.create_publisher(PoseStamped, topic, qos_latched())
                self._pose_pubs[name] = (pub, msg)
            msg.header.stamp = stamp
            msg.header.frame_id = pose.parent
            position, orientation = msg.pose.position, msg.pose.orientation
            position.x, position.y, position.z = pose.translation
            orientation.x, orientation.y, orientation.z, orientation.w = pose.rotation
            pub.publish(msg)

    def on_markers(self) -> None:
        """The graph drawn again when it changed since the last drawing and someone subscribes
        (throttled by the timer: a burst of deltas costs one drawing; with nobody watching, a
        streaming skeleton costs none)."""
        graph = self.core.graph
        if self._version() == self._drawn or not self._markers.get_subscription_count():
            return  # unchanged, or nobody to draw for: drawn when one subscribes
        self._drawn = self._version()
        if len(graph) > MAX_DRAWN_NODES:
            self.get_logger().warning(
                f"{len(graph)} nodes: too many to draw on {topic_names.MARKERS}",
                throttle_duration_sec=60.0,
            )
            return
        stamp = self.get_clock().now().to_msg()
        self._markers.publish(marker_array(drawing(graph), stamp))

    # ------------------------------------------------------------------ housekeeping
    def on_heartbeat(self) -> None:
        now = time.time()
        ended = []
        expired = self.core.claims.expired(now)
        if expired:
            ended.append(self.core.end_claims(expired, "expired", now))
        claims_gone, info_gone = self._gone_agents(now)
        ended.append(self.core.end_claims_of(claims_gone, "agent-gone", now))
        ended.append(self.core.mark_gone(info_gone, now))
        ended += self._check_presence(now)
        if any(ended):
            self._accept([d for d in ended if d is not None])
        self._beat(now)
        self._tf.refresh(self.core.graph)

    def on_presence(self) -> None:
        """An agent's request topic changed liveliness: tell everyone now, not at the next beat."""
        now = time.time()
        ended = [d for d in self._check_presence(now) if d is not None]
        if ended:
            self._accept(ended)
        self._beat(now)

    def _beat(self, now: float) -> None:
        beat = {
            "seq": self.core.seq,
            "stamp": now,
            "boot": self._boot,
            "durable": self.journal.durable,
            "unreachable": self.requests.presence.away,
        }
        self._publish(self._heartbeat, topic_names.HEARTBEAT, beat)

    def _check_presence(self, now: float) -> list[dict[str, Any] | None]:
        """The claims of agents out of reach end (protocol/presence.py), and their info nodes
        say gone: no one here can reach them (a killed process is told so within its 1 s
        lease, or as soon as DDS drops its publisher, also when its successor, respawned at
        once, is up already). An agent back in reach writes its state again. The deltas (None:
        nothing to end)."""
        lost, back = self.requests.presence.update(time.monotonic())
        ended = self.requests.presence.take_ended()
        for agent in ended:
            self.get_logger().info(
                f"a process of {agent} ended (its presence publisher dropped, or lapsed while "
                "another of that name is alive): its info node says gone until one alive "
                "writes its state"
            )
        for agent in lost:
            self.get_logger().warning(
                f"{agent} is out of reach (its presence topic's DDS liveliness lapsed: a network "
                "cut or a frozen process); its claims end until it is back"
            )
        for agent, seconds in back:
            self.get_logger().info(f"{agent} is back in reach after {seconds:.1f} s")
        away = self.requests.presence.away
        return [
            self.core.end_claims_of(away, "unreachable", now),
            self.core.mark_gone([*lost, *ended], now),
        ]

    def _gone_agents(self, now: float) -> tuple[list[str], list[str]]:
        """(claim holders, described agents) whose processes ended (protocol/absence.py)."""
        holders = {c.agent for c in self.core.claims.all()}
        described = {a for a, state in agent_states(self.core.graph).items() if state != GONE}
        live: set[str] = set()
        if holders or described:  # one query of the ROS graph per heartbeat, when it matters
            graph = self.get_node_names_and_namespaces()
            live = {(ns.rstrip("/") + "/" + name) for name, ns in graph} | {n for n, _ in graph}
        live |= self.requests.presence.alive  # its presence publisher alive: its process runs
        claims_gone, info_gone = self._absences.update(
            holders,
            described,
            live,
            now,
            grace=float_param(self, "agent_grace"),
            info_grace=INFO_GRACE,
            warm=time.monotonic() - self._started >= DISCOVERY,
        )
        for agent in info_gone:
            self.get_logger().info(f"{agent} has left the ROS graph: its info node says gone")
        return claims_gone, info_gone

    # ------------------------------------------------------------------ services
    def on_get_attribute(self, request: GetAttribute.Request, response: GetAttribute.Response):
        answer = queries.read_attribute(
            self.core.graph, request.node, request.attribute, request.edge_to, request.edge_type
        )
        response.found = answer.found
        response.value_json = dumps(answer.value) if answer.found else ""
        response.value_type = answer.value_type
        response.version = answer.version
        response.seq = self.core.seq
        response.error = answer.error
        return response

    def on_get_node(self, request: GetNode.Request, response: GetNode.Response):
        doc = queries.node_json(self.core.graph, request.node)
        response.found = doc is not None
        response.node_json = dumps(doc) if doc is not None else ""
        response.seq = self.core.seq
        response.error = "" if doc is not None else f"no node {request.node!r}"
        return response

    def on_get_blob(self, request: GetBlob.Request, response: GetBlob.Response):
        return blob_answer(self.core.graph, request, response, self.core.seq)

    def on_get_transform(self, request: GetTransform.Request, response: GetTransform.Response):
        response.seq = self.core.seq
        try:
            matrix = queries.transform(
                self.core.graph, request.from_node, request.to_node, request.at
            )
        except LookupFailed as e:
            response.found, response.error = False, str(e)
            return response
        response.found = True
        response.pose_json = dumps(rigid.pose_json(matrix))
        return response

    def on_get_snapshot(self, request: GetSnapshot.Request, response: GetSnapshot.Response):
        layout = request.layout
        if layout not in LAYOUTS:
            # the srv has no error field: an empty snapshot_json says nothing was given
            self.get_logger().warning(
                f"dsr/get_snapshot: unknown layout {layout!r} ('' or {dsr_json.COLUMNS!r})",
                throttle_duration_sec=10.0,
            )
            response.seq = self.core.seq
            return response
        # Late joiners often come together (a launch): encode each state's snapshot once a layout.
        version = self._version()
        if self._snapshot_cache.get(layout, (None,))[0] != version:
            text, blobs = snapshot_text(self.core, layout, known=self.blobs.digest_of_kept)
            signed = self.security.sign(topic_names.GET_SNAPSHOT, text)
            self._snapshot_cache[layout] = (version, self.core.seq, signed, blobs)
        _, response.seq, response.snapshot_json, blobs = self._snapshot_cache[layout]
        for digest, data in blobs.items():  # for the joiner, which holds the snapshot for them
            self.blobs.put(digest, data, verified=True)
            self._blob_pub.publish(blob_message(digest, data))
        return response

    def _version(self) -> tuple[int, int]:
        """What the graph holds now: its seq, and the volatile changes since it started (they
        change it without a seq of their own)."""
        return self.core.seq, self.core.volatile_count


main = main_for(DsrServer)
