"""The agent side of the DSR over ROS 2: an exact replica of the graph kept in a node, and a way
to send transactions and hear whether they were accepted.

    agent = DsrAgent()
    agent.setup(node, timeout_sec=10)          # topics, services, first snapshot requested
    agent.add_listener(lambda deltas, resynced: ...)
    agent.send({"ops": [...]}, on_done=lambda result: ...)

Two-phase construction: ``__init__`` builds pure state, ``setup`` attaches to a node and fails
with ``TimedOutError`` if the server does not answer. Callbacks run in the node's executor.

Subscriptions: dsr/deltas, dsr/rejections, dsr/heartbeat, and with ``blobs=True`` dsr/blobs and
every agent's dsr/blobs/<node name> (found as they appear, every 0.2 s): the bytes of a value
an agent sent come from the agent itself, the server's own (a snapshot's) on dsr/blobs.
Publishers: dsr/transactions/<node name> (protocol/identity.py), dsr/blobs/<node name> (the
bytes of the large binary values its requests reference, protocol/blobs.py), dsr/alarms (a
message the server did not sign, at most one per topic every 5 s).

With DSR_KEYSTORE (protocol/security.py) the agent signs its requests with its node's key, and
reads the deltas, rejections, heartbeats and snapshots only when the server's key signed them:
under enforce anything else is dropped (logged, alarmed), under permissive only logged.
Clients: dsr/get_snapshot.

Every agent describes itself in the graph (model/agent_info.py): its agent info node, named
after its node, says who it is and its state, ``starting`` until its replica is in sync, both
directions are matched and every topic it ``listens_to`` has a publisher, then ``ready``. It is
written again whenever the graph says otherwise (a server restarted from an older state, a gone
mark while the agent lives). Whether it is alive the server knows (presence, the ROS graph): no
heartbeat is written. Tools that only read or send one request (the recorder, the monitor,
``dsr apply``, ``clarc start``) pass ``describe=False``.
"""

from __future__ import annotations

import json
import os
import socket
import time
import uuid
from collections.abc import Callable
from typing import Any

from std_msgs.msg import String

from dsr_graph.exceptions import TimedOutError
from dsr_graph.formats.dsr_json import COLUMNS
from dsr_graph.formats.safe_json import loads_object
from dsr_graph.model import agent_info
from dsr_graph.model.binary import dumps
from dsr_graph.model.collector import collector_paused, settle
from dsr_graph.model.vocabulary import Vocabulary
from dsr_graph.protocol import topic_names
from dsr_graph.protocol.blobs import (
    REF,
    BlobCache,
    attrs_resolver,
    extract,
    refs_in_text,
    resolve,
)
from dsr_graph.protocol.identity import agent_topic
from dsr_graph.protocol.replica import Replica
from dsr_graph.protocol.security import Security
from dsr_graph.protocol.server_core import Result
from dsr_graph.protocol.volatility import is_volatile
from dsr_graph.ros.blob_topics import BlobInbox, blob_message
from dsr_graph.ros.json_topics import READING_ERRORS
from dsr_graph.ros.qos import qos_blobs, qos_latched, qos_requests, qos_stream
from dsr_msgs.msg import Blob
from dsr_msgs.srv import GetSnapshot

AGENT_BLOB_BYTES = 64 * 1024 * 1024  # binary values' bytes an agent keeps, newest first
BLOB_PATIENCE = 0.5  # seconds a delta waits for its binary values' bytes (then: a BlobRef)
BLOB_DISCOVERY_PERIOD = 0.2  # seconds between looks for agents' dsr/blobs/<node name> (blobs=True)
GAP_PATIENCE = 0.3  # seconds a hole may last before a snapshot is fetched (deltas may be in flight)
SNAPSHOT_RETRY = 1.0  # seconds before an unanswered snapshot request is sent again (server restart)
LOUD_RULES = ("policy", "identity")  # refusals logged even when the sender asked no verdict
RESEND_AFTER = 3.0  # seconds before a request with no verdict is sent again (same id: no double)
DUPLICATE_PATIENCE = 0.5  # seconds the delta of a request the server calls a duplicate may take
# seconds without the server's heartbeat (one a second): out of its reach (agents, the monitor)
SERVER_SILENCE = 2.5
DESCRIBE_PERIOD = 0.25  # seconds between looks at whether the agent info node is as it should be


Listener = Callable[
    [list[dict[str, Any]], bool], None
]  # (applied deltas, resynced from a snapshot)


class DsrAgent:
    def __init__(
        self, vocabulary: Vocabulary | None = None, blobs: bool = False, describe: bool = True
    ):
        """``blobs``: receive the bytes of large binary values (camera images) as they change;
        without, the replica holds such a value as a ``BlobRef`` (its digest, type and shape).
        ``describe``: keep an agent info node in the graph (the module's docstring)."""
        self.replica = Replica(vocabulary)
        self.describes = describe
        self.listens_to: list[str] = []  # topics that need a publisher before it is ready
        self.can_do: list[str] = []
        self._started_at = time.time()
        # the process's own: asked once, not at every look at the info node
        self._process = {"pid": os.getpid(), "host": socket.gethostname()}
        self._described = 0.0  # the last look at its info node, time.monotonic()
        self._describing = False  # an info write is on its way
        self.wants_blobs = blobs
        self.blobs = BlobCache(AGENT_BLOB_BYTES)
        # deltas and snapshots waiting for the bytes of their binary values, in order
        self._held: list[tuple[float, dict[str, Any], set[str], Callable[[dict], None]]] = []
        self.node = None
        self.name = ""
        self._listeners: list[Listener] = []
        self._pending: dict[str, Callable[[Result], None] | None] = {}
        self._unanswered: dict[str, tuple[str, float]] = {}  # id -> (request text, last sent)
        # id -> (seq, when the server said so), for requests sent again it had accepted
        self._accepted_before: dict[str, tuple[int, float]] = {}
        self._boot = ""  # the server's start, from its heartbeat
        self._heard: float | None = None
        # the last silence of the server's heartbeat: (last beat before it, first beat after)
        self.server_gap = (float("-inf"), float("-inf"))
        self.out_of_reach: frozenset[str] = frozenset()  # agents the server cannot hear now
        self.reach_losses = 0  # how often an agent went out of the server's reach (heartbeat)
        self._outbox: list[str] = []
        # the server was lost (its heartbeat silent, or its subscription gone): requests wait
        # for its next heartbeat, so that a restarted server gets the unanswered ones first
        self._server_lost = False
        self._run = uuid.uuid4().hex[:6]
        self._count = 0
        self._snapshot_future = None
        self._loading = False
        self._snapshot_asked = 0.0
        self._gap_since: float | None = None
        # (deltas applied, when that count was reached): a replica still advancing is behind,
        # not broken
        self._progress = (0, 0.0)
        self.resyncs = 0
        self.security = Security()
        self.forged = 0  # messages dropped because the server did not sign them

    # ------------------------------------------------------------------ set-up
    def setup(self, node, timeout_sec: float = 10.0) -> None:
        self.node = node
        self.name = node.get_fully_qualified_name()
        self.security = Security.from_environment(self.name)
        if self.security.checks and self.security.signer is None:
            node.get_logger().warning(
                f"{self.security.mode}: the keystore {self.security.keystore.root} has no key "
                f"for {self.name}, so the DSR server will refuse its requests (read-only; "
                f"dsr keystore add {self.security.keystore.root} {self.name})"
            )
        self._alarm_pub = node.create_publisher(String, topic_names.ALARMS, qos_stream())
        # a request topic of our own: the server knows who we are from the ROS graph
        self._tx_pub = node.create_publisher(String, agent_topic(node.get_name()), qos_requests())
        self._blob_pub = node.create_publisher(
            Blob, f"{topic_names.BLOBS}/{node.get_name()}", qos_blobs()
        )
        if self.wants_blobs:  # subscribed before the deltas: a blob is taken before its delta
            # any node may publish on a dsr/blobs/<name>: bytes count only under their digest,
            # and no blob larger than all this replica keeps is taken
            self._blob_inbox = BlobInbox(
                node, self.blobs, on_blob=lambda d: self._apply_held(), max_bytes=AGENT_BLOB_BYTES
            )
            self._blob_inbox.listen(topic_names.BLOBS)
            self._listen_to_agents()
            node.create_timer(BLOB_DISCOVERY_PERIOD, self._listen_to_agents)
        self._delta_sub = node.create_subscription(
            String, topic_names.DELTAS, self._on_delta, qos_stream()
        )
        node.create_subscription(String, topic_names.REJECTIONS, self._on_rejection, qos_stream())
        node.create_subscription(String, topic_names.HEARTBEAT, self._on_heartbeat, qos_latched())
        self._snapshot_client = node.create_client(GetSnapshot, topic_names.GET_SNAPSHOT)
        if not self._snapshot_client.wait_for_service(timeout_sec=timeout_sec):
            raise TimedOutError(
                f"no DSR server answered on {topic_names.GET_SNAPSHOT} within {timeout_sec} s "
                "(is dsr_server running with the same ROS_DOMAIN_ID?)"
            )
        node.create_timer(0.05, self._tick)
        self._request_snapshot()

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
        if now - self._described < DESCRIBE_PERIOD or self._describing or not self.replica.synced:
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
            self.node.get_logger().warning(f"could not describe this agent: {result.error}")

    def _listen_to_agents(self) -> None:
        self._blob_inbox.listen_to_agents(self.node.get_topic_names_and_types())

    def add_listener(self, listener: Listener) -> None:
        self._listeners.append(listener)

    @property
    def graph(self):
        return self.replica.graph

    @property
    def boot(self) -> str:
        """The start of the server last heard (new at each restart; "" before its heartbeat)."""
        return self._boot

    @property
    def synced(self) -> bool:
        """A snapshot has been loaded (the graph is the server's, as of some seq)."""
        return self.replica.synced

    @property
    def ready(self) -> bool:
        """Synced with the server, and both directions matched: requests reach the server and
        its deltas reach us (before that, a delta would only be recovered by a resync)."""
        return (
            self.replica.synced
            and self._tx_pub.get_subscription_count() > 0
            and self._delta_sub.get_publisher_count() > 0
        )

    # ------------------------------------------------------------------ sending
    def next_id(self) -> str:
        self._count += 1
        return f"{self.name}:{self._run}:{self._count}"

    def send(self, doc: dict[str, Any], on_done: Callable[[Result], None] | None = None) -> str:
        """Queue a transaction (agent and id are filled in); ``on_done`` gets its ``Result``."""
        doc = dict(doc)
        doc.setdefault("agent", self.name)
        doc.setdefault("id", self.next_id())
        # large binary values go beside the request, as bytes; the JSON names their digests
        doc, blobs = extract(doc)
        for digest, data in blobs.items():  # our own values come back whole to our replica
            self.blobs.put(digest, data, verified=True)
        text = self.security.sign(topic_names.TRANSACTIONS, dumps(doc))
        self._pending[doc["id"]] = on_done
        self._unanswered[doc["id"]] = (text, time.monotonic(), blobs)
        self._outbox.append((text, blobs))
        self._flush_outbox()
        return doc["id"]

    def _send_again(self, older_than: float) -> None:
        """Requests whose verdict has not come (lost to a server that died, or not heard): send
        them again with the same id; the server applies each once and answers the rest."""
        if self._server_lost:
            return  # all of them go again, in order, when the server is heard (_on_heartbeat)
        now = time.monotonic()
        for ident, (text, sent, blobs) in list(self._unanswered.items()):
            if now - sent >= older_than:
                self._unanswered[ident] = (text, now, blobs)
                self._outbox.append((text, blobs))

    def _flush_outbox(self) -> None:
        # A request published before the server's subscription is matched would be lost; one
        # published to a restarted server before it told us it restarted would overtake the
        # requests its predecessor never answered (an agent's writes must apply in its order).
        matched = self._tx_pub.get_subscription_count() > 0  # one rcl query a send
        if self._boot and (not matched or time.monotonic() - (self._heard or 0.0) > SERVER_SILENCE):
            self._server_lost = True
        if self._outbox and not self._server_lost and matched:
            for text, blobs in self._outbox:
                for digest, data in blobs.items():  # the bytes first: the server holds for them
                    self._blob_pub.publish(blob_message(digest, data))
                self._tx_pub.publish(String(data=text))
            self._outbox.clear()

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
        if text is None:
            return
        try:
            delta = loads_object(text, None)
        except READING_ERRORS as e:
            self.node.get_logger().error(f"ignoring a malformed delta: {e!r}")
            return
        self._take(text, delta, self._apply)

    def _take(self, text: str, doc: dict[str, Any], apply: Callable[[dict], None]) -> None:
        """``apply`` ``doc`` (a delta, a snapshot) now, or once the bytes of the binary values it
        references came, behind what is already held (the order is kept)."""
        digests = refs_in_text(text) if self.wants_blobs else set()
        if self._held or any(d not in self.blobs for d in digests):
            self._held.append((time.monotonic(), doc, digests, apply))
            self._apply_held()
        else:
            apply(doc)

    def _apply_held(self) -> None:
        """What is held for the bytes of its binary values, in order, as the bytes come (or
        without them, once BLOB_PATIENCE is over: the value is then a BlobRef)."""
        now = time.monotonic()
        while self._held:
            since, doc, digests, apply = self._held[0]
            if any(d not in self.blobs for d in digests) and now - since < BLOB_PATIENCE:
                return
            self._held.pop(0)
            apply(doc)

    def _apply(self, delta: dict[str, Any]) -> None:
        try:
            applied = self.replica.receive(resolve(delta, self.blobs.get, lazy=True))
        except READING_ERRORS as e:
            self.node.get_logger().error(f"ignoring a malformed delta: {e!r}")
            return
        self._deliver(applied, resynced=False)
        if not applied and is_volatile(delta):  # skipped here, accepted all the same
            self._accepted(delta)

    def _deliver(self, applied: list[dict[str, Any]], resynced: bool) -> None:
        if applied or resynced:
            for listener in list(self._listeners):
                listener(applied, resynced)
        for delta in applied:
            self._accepted(delta)
        now = time.monotonic()
        for ident, (seq, told) in list(self._accepted_before.items()):
            if seq > self.replica.seq:
                continue  # accepted by an earlier send; the replica has not got there yet
            # The delta of that earlier send may still be on its way (deltas and rejections are
            # two topics; a volatile one is never in a snapshot): it answers, if it comes soon.
            if ident in self._pending and now - told < DUPLICATE_PATIENCE:
                continue
            del self._accepted_before[ident]
            callback = self._pending.pop(ident, None)
            if callback is not None:
                callback(Result(ident, True, delta={"seq": seq, "id": ident, "ops": []}))

    def _accepted(self, delta: dict[str, Any]) -> None:
        """The request that made ``delta`` (if it is ours) hears it was accepted."""
        self._unanswered.pop(delta.get("id"), None)
        callback = self._pending.pop(delta.get("id"), None)
        if callback is not None:
            callback(Result(delta["id"], True, delta=delta))

    def _on_rejection(self, msg: String) -> None:
        text = self._from_server(topic_names.REJECTIONS, msg.data)
        if text is None:
            return
        try:
            doc = loads_object(text)
        except ValueError:
            return
        ident = doc.get("id", "")
        if not isinstance(ident, str) or ident not in self._pending:
            return
        self._unanswered.pop(ident, None)
        if isinstance(doc.get("duplicate_of"), int):  # an earlier send of it was accepted
            self._accepted_before[ident] = (doc["duplicate_of"], time.monotonic())
            self._deliver([], resynced=False)
            return
        callback = self._pending.pop(ident)
        reason = doc.get("reason") if isinstance(doc.get("reason"), dict) else {}
        error = doc.get("error") if isinstance(doc.get("error"), str) else ""
        if callback is None and reason.get("rule") in LOUD_RULES:  # a set-up mistake, not a race
            self.node.get_logger().error(f"request {ident} refused: {error}")
        if callback is not None:
            callback(Result(ident, False, reason=reason, error=error))

    @property
    def heard(self) -> float | None:
        """When the server's heartbeat was last heard (time.monotonic()), None before."""
        return self._heard

    def _on_heartbeat(self, msg: String) -> None:
        text = self._from_server(topic_names.HEARTBEAT, msg.data)
        if text is None:
            return  # a forged heartbeat must not make a dead server look alive
        now = time.monotonic()
        before = self._heard
        if before is not None and now - before > SERVER_SILENCE:
            self.server_gap = (before, now)  # a cut (or a dead server) ended
        self._heard = now
        try:
            beat = loads_object(text)
            self.replica.observe_server_seq(int(beat["seq"]))
        except READING_ERRORS:
            return
        listed = beat.get("unreachable", [])
        listed = listed if isinstance(listed, list) else []
        away = frozenset(a for a in listed if isinstance(a, str))
        if away - self.out_of_reach:
            self.reach_losses += 1
        self.out_of_reach = away
        boot = str(beat.get("boot", ""))
        restarted = bool(self._boot) and boot != self._boot
        if restarted and before is not None:
            # a server killed and back within SERVER_SILENCE is a gap all the same: what it held
            # open (an answer's window) opens again only now
            self.server_gap = (before, now)
        if (restarted or self._server_lost) and self._unanswered:
            # the server restarted (what it did not answer may have died with it) or was out of
            # reach: every unanswered request goes again, in the order they were first sent
            # (those sent while it was lost were held for this; the same id is applied once)
            if restarted:
                self.node.get_logger().warning(
                    f"the DSR server restarted: sending {len(self._unanswered)} unanswered "
                    "request(s) again"
                )
            now = time.monotonic()
            self._outbox = []
            for ident, (text, _sent, blobs) in self._unanswered.items():
                self._unanswered[ident] = (text, now, blobs)
                self._outbox.append((text, blobs))
        self._boot = boot
        self._server_lost = False
        self._flush_outbox()

    # ------------------------------------------------------------------ resynchronisation
    def _tick(self) -> None:
        self._apply_held()
        if self.describes:
            self._describe_self(time.monotonic())
        if self._accepted_before:
            self._deliver([], resynced=False)
        self._send_again(older_than=RESEND_AFTER)
        self._flush_outbox()
        now = time.monotonic()
        if self.replica.applied != self._progress[0]:
            self._progress = (self.replica.applied, now)
        if not self.replica.needs_resync:
            self._gap_since = None
            return
        if self._gap_since is None:
            self._gap_since = now
        # The heartbeat says the server is ahead: a hole (a later delta came, an earlier did not)
        # or a replica that stopped advancing means deltas were lost; one still applying deltas
        # is only behind, and a snapshot would slow it down further.
        stalled = now - self._progress[1] >= GAP_PATIENCE
        if self.replica.synced and not self.replica.has_hole and not stalled:
            self._gap_since = now
        if self._snapshot_future is not None and now - self._snapshot_asked >= SNAPSHOT_RETRY:
            # lost (e.g. sent to a server that was being restarted): withdraw it and ask again
            self._snapshot_client.remove_pending_request(self._snapshot_future)
            self._snapshot_future = None
        if (
            (not self.replica.synced or now - self._gap_since >= GAP_PATIENCE)
            and self._snapshot_future is None
            and not self._loading
        ):
            self._request_snapshot()

    def _request_snapshot(self) -> None:
        self._snapshot_asked = time.monotonic()
        # column by column: the elements it does not use are never parsed (dsr_json.to_columns)
        future = self._snapshot_client.call_async(GetSnapshot.Request(layout=COLUMNS))
        self._snapshot_future = future
        future.add_done_callback(self._on_snapshot)

    def _on_snapshot(self, future) -> None:
        if future is not self._snapshot_future:
            return  # an answer to a request already given up on
        self._snapshot_future = None
        try:
            response = future.result()
            text = self._from_server(topic_names.GET_SNAPSHOT, response.snapshot_json)
            if text is None:
                return  # not the server's: the tick asks again
            with collector_paused():  # restored as trusted: not walked (safe_json.loads)
                snapshot = loads_object(text, None, walk=False)
                settle()  # its dicts become the replica's (model/collector.py)
        except Exception as e:  # a failed call or a bad snapshot: the tick asks again
            self.node.get_logger().warning(f"snapshot failed, will retry: {e!r}")
            return
        self._loading = True  # not asked again while it waits for its binary values' bytes
        # each element's attributes are looked at for references only when there are some
        hook = attrs_resolver(self.blobs.get) if REF in text else None
        self._take(text, snapshot, lambda doc: self._load(doc, hook))

    def _load(self, snapshot: dict[str, Any], hook) -> None:
        self._loading = False
        try:
            applied = self.replica.load_snapshot(snapshot, hook)
        except Exception as e:  # a bad snapshot: the tick asks again
            self.node.get_logger().warning(f"snapshot failed, will retry: {e!r}")
            return
        settle()  # the replica is most of this process now (model/collector.py)
        self.resyncs += 1
        self._gap_since = None
        if self.resyncs > 1:  # the first is the start; later ones mean deltas were missed
            self.node.get_logger().info(
                f"resynchronised from a snapshot at seq {self.replica.seq} (deltas were missed: "
                "the server restarted or was out of reach)"
            )
        self._deliver(applied, resynced=True)
