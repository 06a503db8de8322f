"""The agent's side of the DSR protocol without a transport: the replica, the requests waiting for
a verdict, and every rule that keeps both right through lost, repeated and late messages and a
server that restarts. ``ros/agent.py`` (DsrAgent) runs it over ROS 2, ``local_bus.py`` (LocalAgent)
in one process, and the unit tests over a transport that loses, repeats and reorders at will.

    core = AgentCore("/speech", link, run="a1b2c3")
    core.send({"ops": [...]}, on_done=lambda result: ..., now=now)
    core.on_delta(text, now); core.on_rejection(text, now); core.on_heartbeat(text, now)
    core.on_durable(text, now)           # the server's group commit reached a seq
    core.on_snapshot(text, now)          # the answer to link.ask_snapshot()
    core.tick(now)                       # every TICK s: resends, held deltas, resyncs

The rules:
- a request goes out only while the server's request subscription is matched and the server is
  heard; one sent to a restarted server before it said so would overtake the requests its
  predecessor never answered (an agent's writes apply in its order);
- a request with no verdict after RESEND_AFTER goes again with the same id, and every unanswered
  one goes again, in order, when the server restarted or is heard after a silence, and once a
  snapshot is loaded (it may hold a request's delta, which then never comes); the server
  applies an id once and answers a repeat with the seq that accepted it (``duplicate_of``), whose
  verdict is given once the replica has reached that seq;
- a change is visible before it is durable: the server broadcasts a delta at once and makes it
  durable in a group commit; every delta, heartbeat and durability notice says the server's boot
  and its durable seq, and the writer's verdict waits until its delta is durable (a server that
  tells no durable seq, as LocalBus, broadcasts only durable deltas);
- a server that restarted may have lost what it had not made durable: a replica holding more
  than the last durable seq it heard resyncs from a snapshot, the deltas kept aside from the old
  server are dropped, and every request still without its verdict goes again (the new server
  knows the ids it kept). A late message of the old server (another topic, queued) counts as
  one more restart: what the replica and the verdicts hold is always of the boot heard last,
  and the next message of the new server brings them back to it;
- a delta waits, behind those before it, for the bytes of the binary values it references (at
  most BLOB_PATIENCE, then the value is a BlobRef);
- a replica the server is ahead of asks for a snapshot once a hole has lasted GAP_PATIENCE or it
  stopped advancing (one still applying deltas is only behind), and asks again after
  SNAPSHOT_RETRY when no answer came.
Times are the caller's clock (time.monotonic() over ROS, the virtual clock of a LocalBus).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any, Protocol

from dsr_graph.formats.safe_json import READING_ERRORS, loads_object
from dsr_graph.model.binary import compact
from dsr_graph.model.vocabulary import Vocabulary
from dsr_graph.protocol.blobs import REF, BlobCache, attrs_resolver, extract, refs_in_text, resolve
from dsr_graph.protocol.replica import Replica
from dsr_graph.protocol.server_core import Result
from dsr_graph.protocol.volatility import is_volatile

AGENT_BLOB_BYTES = 64 * 1024 * 1024  # binary values' bytes an agent keeps, newest first
BLOB_PATIENCE = 0.5  # seconds a delta waits for its binary values' bytes (then: a BlobRef)
GAP_PATIENCE = 0.3  # seconds a hole may last before a snapshot is fetched (deltas may be in flight)
SNAPSHOT_RETRY = 1.0  # seconds before an unanswered snapshot request is sent again (server restart)
LOUD_RULES = ("policy", "identity")  # refusals logged even when the sender asked no verdict
RESEND_AFTER = 3.0  # seconds before a request with no verdict is sent again (same id: no double)
DUPLICATE_PATIENCE = 0.5  # seconds the delta of a request the server calls a duplicate may take
# seconds without the server's heartbeat (one a second): out of its reach (agents, the monitor)
SERVER_SILENCE = 2.5
TICK = 0.05  # seconds between ticks (the transport's timer) while the core is ``busy``
# and while it is not: what a tick then does (the server's silence, the agent's info node) can
# wait that long; with 20 wake-ups a second an idle agent took 0.7 to 0.9% of a core, 0.4% at 4
IDLE_TICK = 0.25

Listener = Callable[[list[dict[str, Any]], bool], None]  # (applied deltas, resynced)
Verdict = Callable[[Result], None]


class Link(Protocol):
    """What the core needs from its transport."""

    def publish(self, text: str, blobs: dict[str, bytes]) -> None:
        """Send a request (the bytes of its binary values first: the server holds for them)."""

    def matched(self) -> bool:
        """The server's subscription to this agent's requests is matched."""

    def ask_snapshot(self) -> None:
        """Ask the server for a snapshot: answered by ``on_snapshot`` or ``snapshot_failed``."""

    def withdraw_snapshot(self) -> None:
        """Give up the snapshot asked for: an answer to it that comes later is not given."""

    def log(self, level: str, message: str) -> None:
        """``level``: "info", "warning" or "error"."""


class AgentCore:
    def __init__(
        self,
        name: str,
        link: Link,
        run: str,
        vocabulary: Vocabulary | None = None,
        blobs: bool = False,
    ):
        """``run`` tells this agent's request ids from those of an earlier one of that name.
        ``blobs``: wait for the bytes of binary values (else the replica holds a BlobRef)."""
        self.name = name
        self.link = link
        self.run = run
        self.replica = Replica(vocabulary)
        self.wants_blobs = blobs
        self.blobs = BlobCache(AGENT_BLOB_BYTES)
        self._listeners: list[Listener] = []
        self._count = 0
        self._pending: dict[str, Verdict | None] = {}
        # id -> (request text, last sent, its binary values' bytes)
        self._unanswered: dict[str, tuple[str, float, dict[str, bytes]]] = {}
        # id -> (seq, when the server said so), for requests sent again it had accepted
        self._accepted_before: dict[str, tuple[int, float]] = {}
        self._outbox: list[tuple[str, dict[str, bytes]]] = []
        # deltas and snapshots waiting for the bytes of their binary values, in order
        self._held: list[tuple[float, dict[str, Any], set[str], Callable[[dict, float], None]]] = []
        self.boot = ""  # the server's start, from its messages ("" before)
        # the server's durable seq as last told; None: it tells none (its deltas are durable)
        self.durable: int | None = None
        # id -> the delta of a request of ours, seen but not yet durable (its verdict waits)
        self._undurable: dict[str, dict[str, Any]] = {}
        self.heard: float | None = None  # when its heartbeat was last heard
        # the last silence of the server's heartbeat: (last beat before it, first beat after)
        self.server_gap = (float("-inf"), float("-inf"))
        self.out_of_reach: frozenset[str] = frozenset()  # agents the server cannot hear now
        self.reach_losses = 0  # how often an agent went out of the server's reach (heartbeat)
        # the server was lost (its heartbeat silent, or its subscription gone): requests wait
        # for its next heartbeat, so that a restarted server gets the unanswered ones first
        self._server_lost = False
        self._asking = False  # a snapshot was asked for and not answered
        self._asked_boot = ""  # the server heard when it was asked for
        self._asked_at = 0.0
        self._loading = False  # a snapshot waits for its binary values' bytes
        self._gap_since: float | None = None
        # (deltas applied, when that count was reached): a replica still advancing is behind,
        # not broken
        self._progress = (0, 0.0)
        self.resyncs = 0
        self.closed = False

    @property
    def graph(self):
        return self.replica.graph

    @property
    def synced(self) -> bool:
        return self.replica.synced

    @property
    def busy(self) -> bool:
        """A tick may have something to do: a verdict, a delta or a snapshot is awaited."""
        return bool(
            self._unanswered
            or self._accepted_before
            or self._undurable
            or self._held
            or self._outbox
            or self.replica.needs_resync
        )

    def add_listener(self, listener: Listener) -> None:
        self._listeners.append(listener)

    def close(self) -> None:
        """The agent stops: nothing it is waiting for is given any more."""
        self.closed = True
        self._listeners.clear()
        self._pending.clear()
        self._unanswered.clear()
        self._accepted_before.clear()
        self._undurable.clear()
        self._outbox.clear()
        self._held.clear()

    # ------------------------------------------------------------------ sending
    def next_id(self) -> str:
        self._count += 1
        return f"{self.name}:{self.run}:{self._count}"

    def send(
        self, doc: dict[str, Any], on_done: Verdict | None, now: float, sign=lambda text: text
    ) -> str:
        """Queue a transaction (agent and id are filled in); ``on_done`` gets its ``Result``.
        ``sign``: the request's text as it goes on the wire (protocol/security.py)."""
        if self.closed:
            return ""
        doc = dict(doc)
        doc.setdefault("agent", self.name)
        doc.setdefault("id", self.next_id())
        # large binary values go beside the request, as bytes; the JSON names their digests,
        # and sensor data's names this agent, whose sensor blob topic alone carries its bytes
        volatile, at = self.replica.graph.vocabulary.volatile, self.name.rsplit("/", 1)[-1]
        doc, blobs = extract(doc, sensor_at=lambda attribute: at if attribute in volatile else None)
        for digest, data in blobs.items():  # our own values come back whole to our replica
            self.blobs.put(digest, data, verified=True)
        text = sign(compact(doc))
        self._pending[doc["id"]] = on_done
        self._unanswered[doc["id"]] = (text, now, blobs)
        self._outbox.append((text, blobs))
        self._flush(now)
        return doc["id"]

    def _send_again(self, now: float, after: float = RESEND_AFTER) -> None:
        """Requests whose verdict has not come for ``after`` seconds (lost to a server that
        died, or not heard): send them again with the same id; the server applies each once and
        answers the rest."""
        if self._server_lost:
            return  # all of them go again, in order, when the server is heard (on_heartbeat)
        for ident, (text, sent, blobs) in list(self._unanswered.items()):
            waiting = ident in self._undurable or ident in self._accepted_before
            if now - sent >= after and not waiting:
                self._unanswered[ident] = (text, now, blobs)
                self._outbox.append((text, blobs))

    def _flush(self, now: float) -> None:
        # A request published before the server's subscription is matched would be lost; one
        # published to a restarted server before it told us it restarted would overtake the
        # requests its predecessor never answered. Unmatched, even before its first heartbeat,
        # the server is lost until it is heard.
        matched = self.link.matched()
        silent = bool(self.boot) and now - (self.heard or 0.0) > SERVER_SILENCE
        if not matched or silent:
            self._server_lost = True
        if self._outbox and not self._server_lost and matched:
            outbox, self._outbox = self._outbox, []
            for text, blobs in outbox:
                self.link.publish(text, blobs)

    # ------------------------------------------------------------------ receiving
    def on_delta(self, text: str, now: float) -> None:
        """A delta's text, as the server signed it (checked by the transport)."""
        if self.closed:
            return
        try:
            delta = loads_object(text, None)
        except READING_ERRORS as e:
            self.link.log("error", f"ignoring a malformed delta: {e!r}")
            return
        self._server_said(delta, now)
        self._take(text, delta, self._apply, now)

    def on_durable(self, text: str, now: float) -> None:
        """The server's durability notice ({boot, durable}), after each group commit."""
        try:
            self._server_said(loads_object(text), now)
        except READING_ERRORS:
            return

    def _server_said(self, doc: dict[str, Any], now: float) -> None:
        """Take the boot and the durable seq a server's message carries."""
        boot = doc.get("boot")
        if isinstance(boot, str) and boot and boot != self.boot:
            self._server_restarted(boot, now)
        durable = doc.get("durable")
        if isinstance(durable, int) and not isinstance(durable, bool):
            if self.durable is None or durable > self.durable:
                self.durable = durable
                self._release_durable(now)

    def _server_restarted(self, boot: str, now: float) -> None:
        """A new server (or the first heard). What the old one had not made durable may be lost:
        the replica resyncs if it holds any of it, and every request without its verdict goes
        again, in order (the same id is applied once: the new server knows those it kept)."""
        before, self.boot = self.boot, boot
        if not before:
            return
        if self.heard is not None:
            # a server killed and back within SERVER_SILENCE is a gap all the same: what it held
            # open (an answer's window) opens again only now
            self.server_gap = (self.heard, now)
        ahead = self.durable is not None and self.replica.seq > self.durable
        self.replica.server_restarted(resync=ahead)
        if ahead:
            self.link.log(
                "warning",
                f"the DSR server restarted: this replica saw changes up to seq "
                f"{self.replica.seq}, durable only up to {self.durable}; resynchronising",
            )
        self.durable = None
        self._undurable.clear()
        self._held.clear()  # the old server's deltas, waiting for bytes: maybe lost
        self._loading = False
        self._accepted_before.clear()
        if self._unanswered:
            self.link.log(
                "warning",
                f"the DSR server restarted: sending {len(self._unanswered)} unanswered "
                "request(s) again",
            )
            self._outbox = []
            for ident, (request, _sent, blobs) in self._unanswered.items():
                self._unanswered[ident] = (request, now, blobs)
                self._outbox.append((request, blobs))
        self._flush(now)

    def _durable_enough(self, seq: int) -> bool:
        return self.durable is None or seq <= self.durable

    def _release_durable(self, now: float) -> None:
        """Verdicts whose deltas the server has now made durable."""
        for ident, delta in list(self._undurable.items()):
            if self._durable_enough(delta["seq"]):
                del self._undurable[ident]
                self._unanswered.pop(ident, None)
                callback = self._pending.pop(ident, None)
                if callback is not None:
                    callback(Result(ident, True, delta=delta))
        if self._accepted_before:
            self._deliver([], False, now)

    def blob_arrived(self, now: float) -> None:
        """The bytes of a binary value came (the cache has them): what waited for them goes on."""
        self._apply_held(now)

    def _take(
        self, text: str, doc: dict[str, Any], apply: Callable[[dict, float], None], now: float
    ) -> None:
        """``apply`` ``doc`` (a delta, a snapshot) now, or once the bytes of the binary values it
        references came, behind what is already held (the order is kept)."""
        digests = refs_in_text(text) if self.wants_blobs else set()
        if self._held or any(d not in self.blobs for d in digests):
            self._held.append((now, doc, digests, apply))
            self._apply_held(now)
        else:
            apply(doc, now)

    def _apply_held(self, now: float) -> None:
        while self._held:
            since, doc, digests, apply = self._held[0]
            if any(d not in self.blobs for d in digests) and now - since < BLOB_PATIENCE:
                return
            self._held.pop(0)
            apply(doc, now)

    def _apply(self, delta: dict[str, Any], now: float) -> None:
        try:
            applied = self.replica.receive(resolve(delta, self.blobs.get, lazy=True))
        except READING_ERRORS as e:
            self.link.log("error", f"ignoring a malformed delta: {e!r}")
            return
        self._deliver(applied, False, now)
        if not applied and is_volatile(delta):  # skipped here, accepted all the same
            self._accepted(delta)

    def _deliver(self, applied: list[dict[str, Any]], resynced: bool, now: float) -> None:
        if applied or resynced:
            for listener in list(self._listeners):
                listener(applied, resynced)
        for delta in applied:
            self._accepted(delta)
        for ident, (seq, told) in list(self._accepted_before.items()):
            if seq > self.replica.seq or not self._durable_enough(seq):
                continue  # accepted by an earlier send; the replica (or disk) is not there yet
            # The delta of that earlier send may still be on its way (deltas and rejections are
            # two topics; a volatile one is never in a snapshot): it answers, if it comes soon.
            if ident in self._pending and now - told < DUPLICATE_PATIENCE:
                continue
            del self._accepted_before[ident]
            self._unanswered.pop(ident, None)
            callback = self._pending.pop(ident, None)
            if callback is not None:
                callback(Result(ident, True, delta={"seq": seq, "id": ident, "ops": []}))

    def _accepted(self, delta: dict[str, Any]) -> None:
        """The request that made ``delta`` (if it is ours) hears it was accepted, once it is
        durable (a volatile one is never journalled: at once)."""
        ident = delta.get("id")
        if ident not in self._unanswered and ident not in self._pending:
            return  # another agent's, or answered already
        durable = "durable" not in delta or is_volatile(delta)
        if not durable and not self._durable_enough(delta["seq"]):
            self._undurable[ident] = delta  # still unanswered: a restart sends it again
            return
        self._undurable.pop(ident, None)
        self._unanswered.pop(ident, None)
        self._accepted_before.pop(ident, None)
        callback = self._pending.pop(ident, None)
        if callback is not None:
            callback(Result(delta["id"], True, delta=delta))

    def on_rejection(self, text: str, now: float) -> None:
        """A rejection's text (any agent's: those of others are ignored)."""
        try:
            doc = loads_object(text)
        except READING_ERRORS:
            return
        ident = doc.get("id", "")
        if not isinstance(ident, str) or ident not in self._pending:
            return
        if isinstance(doc.get("duplicate_of"), int):  # an earlier send of it was accepted
            # still unanswered: if the server restarts before it is durable, it goes again
            self._accepted_before[ident] = (doc["duplicate_of"], now)
            return
        self._unanswered.pop(ident, None)
        callback = self._pending.pop(ident)
        reason = doc.get("reason") if isinstance(doc.get("reason"), dict) else {}
        error = doc.get("error") if isinstance(doc.get("error"), str) else ""
        if callback is None and reason.get("rule") in LOUD_RULES:  # a set-up mistake, not a race
            self.link.log("error", f"request {ident} refused: {error}")
        if callback is not None:
            callback(Result(ident, False, reason=reason, error=error))

    def on_heartbeat(self, text: str, now: float) -> None:
        """The server's heartbeat: its seq, its boot (new at each start), its durable seq and who
        is out of reach."""
        before = self.heard
        try:
            beat = loads_object(text)
            seq = int(beat["seq"])
        except READING_ERRORS:
            self.heard = now
            return
        if before is not None and now - before > SERVER_SILENCE:
            self.server_gap = (before, now)  # a cut (or a dead server) ended
        self._server_said(beat, now)
        self.heard = now
        self.replica.observe_server_seq(seq)
        listed = beat.get("unreachable", [])
        listed = listed if isinstance(listed, list) else []
        away = frozenset(a for a in listed if isinstance(a, str))
        if away - self.out_of_reach:
            self.reach_losses += 1
        self.out_of_reach = away
        if self._server_lost and self._unanswered:
            # what it did not answer may never have reached it: every unanswered request goes
            # again, in the order they were first sent (those sent while it was lost were held
            # for this; the same id is applied once)
            self._outbox = []
            for ident, (request, _sent, blobs) in self._unanswered.items():
                self._unanswered[ident] = (request, now, blobs)
                self._outbox.append((request, blobs))
        self._server_lost = False
        self._flush(now)

    # ------------------------------------------------------------------ resynchronisation
    def tick(self, now: float) -> None:
        if self.closed:
            return
        self._apply_held(now)
        if self._accepted_before:
            self._deliver([], False, now)
        self._send_again(now)
        self._flush(now)
        if self.replica.applied != self._progress[0]:
            self._progress = (self.replica.applied, now)
        if not self.replica.needs_resync:
            self._gap_since = None
            return
        if self._gap_since is None:
            self._gap_since = now
        # The server is ahead: a hole (a later delta came, an earlier did not) or a replica that
        # stopped advancing means deltas were lost; one still applying deltas is only behind,
        # and a snapshot would slow it down further.
        stalled = now - self._progress[1] >= GAP_PATIENCE
        if self.replica.synced and not self.replica.has_hole and not stalled:
            self._gap_since = now
        if self._asking and now - self._asked_at >= SNAPSHOT_RETRY:
            # lost (e.g. sent to a server that was being restarted): withdraw it and ask again
            self.link.withdraw_snapshot()
            self._asking = False
        if (
            (not self.replica.synced or now - self._gap_since >= GAP_PATIENCE)
            and not self._asking
            and not self._loading
        ):
            self.ask_snapshot(now)

    def ask_snapshot(self, now: float) -> None:
        self._asking = True
        self._asked_at = now
        self._asked_boot = self.boot
        self.link.ask_snapshot()

    def snapshot_failed(self, problem: str) -> None:
        """The snapshot asked for did not come (a failed call): the tick asks again."""
        self._asking = False
        self.link.log("warning", f"snapshot failed, will retry: {problem}")

    def on_snapshot(self, text: str, now: float) -> None:
        """The snapshot asked for, as the server signed it."""
        self._asking = False
        if self.closed:
            return
        if self._asked_boot and self._asked_boot != self.boot:
            return  # asked of a server that restarted since: it may hold what was lost
        try:
            # restored as trusted: not walked (safe_json.loads)
            snapshot = loads_object(text, None, walk=False)
        except READING_ERRORS as e:
            self.link.log("warning", f"snapshot failed, will retry: {e!r}")
            return
        self._loading = True  # not asked again while it waits for its binary values' bytes
        # each element's attributes are looked at for references only when there are some
        hook = attrs_resolver(self.blobs.get) if REF in text else None
        self._take(text, snapshot, lambda doc, now: self._load(doc, hook, now), now)

    def _load(self, snapshot: dict[str, Any], hook, now: float) -> None:
        self._loading = False
        try:
            applied = self.replica.load_snapshot(snapshot, hook)
        except Exception as e:  # a bad snapshot, whatever it broke: the tick asks again
            self.link.log("warning", f"snapshot failed, will retry: {e!r}")
            return
        self.resyncs += 1
        self._gap_since = None
        if self.resyncs > 1:  # the first is the start; later ones mean deltas were missed
            self.link.log(
                "info",
                f"resynchronised from a snapshot at seq {self.replica.seq} (deltas were missed: "
                "the server restarted or was out of reach)",
            )
        self._deliver(applied, True, now)
        # A request whose delta the snapshot took (dropped while it was awaited) has no verdict
        # coming: asked again now, the server answers "duplicate_of" and the replica has that
        # seq. Left to RESEND_AFTER, every agent's next write after a server restart waited
        # 3 s, and PELEA with it (an agent info node's "ready" among them).
        self._send_again(now, after=0.0)
        self._flush(now)
