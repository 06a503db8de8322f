"""The DSR server's logic without ROS: validate a request, apply it, number it, and describe the
accepted change as a delta (or the rejection with its reason). The ROS node
(``server_node.py``) only moves text between topics, this core and the state store.

Delta (JSON, one per accepted transaction, in sequence order; see docs/FORMAT.md):
    {"seq": 12, "stamp": 1764000000.5, "agent": "/speech", "id": "speech-7",
     "ops": [canonical ops], "claims": {"granted": [...], "released": [...]}}
A change that only sets volatile values (sensor data, ``volatility.py``) takes no seq of its
own: its delta carries the seq it follows and ``"volatile": n``, and it is not journalled.
"""

from __future__ import annotations

import time
from collections import OrderedDict
from collections.abc import Callable, Container, Iterable
from dataclasses import dataclass
from typing import Any

from dsr_graph.exceptions import MissingBlob, TransactionRejected, ValueTypeError, Violation
from dsr_graph.formats import dsr_json, safe_json, units
from dsr_graph.model import provenance
from dsr_graph.model.agent_info import ended_run, gone_ops
from dsr_graph.model.binary import declared_size
from dsr_graph.model.claims import Claim, ClaimTable, released, target_key, touched
from dsr_graph.model.graph import Graph
from dsr_graph.model.policy import OPEN, Policy
from dsr_graph.model.transaction import apply_ops, parse_transaction
from dsr_graph.protocol.blobs import NODE_NAME, resolve
from dsr_graph.protocol.volatility import VOLATILE, only_volatile, without_absent_volatile

SERVER_AGENT = "dsr_server"
REMEMBERED_IDS = 100_000  # request ids kept in memory to recognise a request sent again
SNAPSHOT_IDS = 2_000  # of them, kept in the persisted snapshot (the journal holds the rest)
DEFAULT_MAX_REQUEST_BYTES = 4 * 1024 * 1024  # UTF-8 bytes
DEFAULT_MAX_OPS = 10_000  # operations in one transaction
DEFAULT_MAX_NODES = 1_000_000  # nodes in the graph
DEFAULT_MAX_LEASE = 300.0  # seconds a claim may last before it must be taken again
DEFAULT_MAX_VALUE_BYTES = 8 * 1024 * 1024  # one binary value (an image): 8 MiB


@dataclass
class Result:
    """What became of a transaction: accepted with its delta, or rejected with the reason."""

    id: str
    accepted: bool
    delta: dict[str, Any] | None = None
    reason: dict[str, Any] | None = None
    error: str = ""

    @property
    def seq(self) -> int | None:
        return None if self.delta is None else self.delta["seq"]


@dataclass
class Rejection:
    id: str
    agent: str
    violation: Violation
    duplicate_of: int | None = None  # the seq that accepted this request when it came first

    def to_json(self) -> dict[str, Any]:
        doc = {
            "id": self.id,
            "agent": self.agent,
            "reason": self.violation.to_json(),
            "error": str(self.violation),
        }
        if self.duplicate_of is not None:
            doc["duplicate_of"] = self.duplicate_of
        return doc


class Duplicate(TransactionRejected):
    """A request the server already accepted (an agent sent it again after a restart)."""

    def __init__(self, ident: str, seq: int):
        super().__init__(
            Violation(
                "duplicate", "transaction", f"request {ident!r} was already accepted as seq {seq}"
            )
        )
        self.seq = seq


class ServerCore:
    def __init__(
        self,
        graph: Graph,
        seq: int = 0,
        claims: ClaimTable | None = None,
        max_request_bytes: int = DEFAULT_MAX_REQUEST_BYTES,
        policy: Policy = OPEN,
        max_ops: int = DEFAULT_MAX_OPS,
        max_nodes: int = DEFAULT_MAX_NODES,
        max_lease: float = DEFAULT_MAX_LEASE,
        max_value_bytes: int = DEFAULT_MAX_VALUE_BYTES,
    ):
        self.graph = graph
        self.policy = policy  # who may write what, and every claim's priority
        self.seq = seq
        self.volatile_count = 0  # volatile deltas since this core started
        self.claims = claims if claims is not None else ClaimTable()
        self.max_request_bytes = max_request_bytes
        # the server's own deltas committed while a request was taken (take_server_deltas)
        self._server_deltas: list[dict[str, Any]] = []
        self.max_ops = max_ops
        self.max_nodes = max_nodes
        self.max_lease = max_lease
        self.max_value_bytes = max_value_bytes
        # request id -> seq, for the most recent requests: a request sent again (the agent
        # did not hear the verdict, e.g. the server restarted) is answered, not applied twice
        self.accepted_ids: OrderedDict[str, int] = OrderedDict()

    # ------------------------------------------------------------------ requests
    def submit(
        self,
        text: str,
        now: float | None = None,
        sender: str | None = None,
        blobs: Callable[[str], bytes | None] = lambda digest: None,
    ) -> Any:
        """A delta (dict) if the request was accepted, else a ``Rejection``. Never raises for
        bad input: anything a client can send ends in one of the two. ``sender``: the node the
        ROS graph shows sent it (the server's), which the delta names; None only where no
        middleware is involved (pure tests), and then the request's own ``agent`` is taken.
        ``blobs``: the bytes of the binary values the request references (protocol/blobs.py)
        by digest, None for one that has not come."""
        now = time.time() if now is None else now
        ident, agent = "", sender or ""
        try:
            doc = self._read(text)
            ident = _id_of(doc)
            if isinstance(doc, dict):
                if sender is None:
                    agent = doc["agent"] if isinstance(doc.get("agent"), str) else ""
                # sensor data's bytes stay with its writer: the reference names it
                doc = _with_blobs(doc, blobs, self.graph.vocabulary.volatile, agent)
            return self.submit_doc(doc, now, sender)
        except Duplicate as e:
            return Rejection(ident, agent, e.violation, duplicate_of=e.seq)
        except TransactionRejected as e:
            return Rejection(ident, agent, e.violation)

    def _read(self, text: str | bytes) -> Any:
        """The request's JSON (safe_json: bytes, depth, numbers bounded), or a rejection."""
        raw = text.encode("utf-8", "surrogatepass") if isinstance(text, str) else text
        size = len(raw)  # encoded once: the reader takes the bytes
        if size > self.max_request_bytes:
            raise TransactionRejected(
                Violation(
                    "too-large",
                    "transaction",
                    f"request of {size} bytes exceeds max_request_bytes ({self.max_request_bytes})",
                )
            )
        try:
            return safe_json.loads(raw, None)
        except ValueError as e:
            raise TransactionRejected(Violation("malformed", "transaction", str(e))) from None

    def unattributed(self, text: str, violation: Violation) -> Rejection:
        """The answer to a request whose sender cannot be proven: refused, its id kept (when it
        has one) so that the agent that sent it hears why."""
        try:
            doc = self._read(text)
        except TransactionRejected:
            doc = None
        return Rejection(_id_of(doc), "", violation)

    def submit_doc(self, doc: Any, now: float, sender: str | None = None) -> dict[str, Any]:
        if sender is not None and isinstance(doc, dict):
            declared = doc.get("agent")
            if declared not in (None, "", sender):
                raise TransactionRejected(
                    Violation(
                        "identity",
                        f"agent {declared!r}",
                        f"the request says it comes from {declared!r}, but the ROS graph shows "
                        f"{sender!r} sent it",
                    )
                )
            doc = {**doc, "agent": sender}
        tx = parse_transaction(doc)
        self._check_limits(tx)
        # a request's own priority is never trusted: it comes from the policy
        tx.priority = self.policy.priority_of(tx.agent)
        if tx.id and tx.id in self.accepted_ids:
            raise Duplicate(tx.id, self.accepted_ids[tx.id])
        if ended_run(self.graph, tx.agent, tx.id):
            # A new run of the agent writes while its info node shows the one before: that
            # process ended, whatever the server heard of it (its liveliness news, read late on
            # a loaded machine, may show no change at all: a lapse, a drop and the successor's
            # match read as one). Readers see the end before the new run's first change.
            gone = self.mark_gone([tx.agent], now)
            if gone is not None:
                self._server_deltas.append(gone)
        self.policy.check(self.graph, tx.agent, tx.ops)
        self.policy.check_claims(self.graph, tx.agent, tx.claim)
        claim_keys = [target_key(t, f"claim {i}") for i, t in enumerate(tx.claim)]
        for key in claim_keys:
            for name in [key[1]] if key[0] == "node" else [key[1], key[2]]:
                if name not in self.graph:
                    raise TransactionRejected(
                        Violation(
                            "node-missing",
                            f"claim on {name!r}",
                            f"node {name!r} does not exist",
                            "claim",
                        )
                    )
        release_keys = (
            None if tx.release == "all" else [target_key(t, "release") for t in tx.release]
        )

        written = [key for op in tx.ops for key in touched(self.graph, op)]
        preempted = self.claims.check(tx.agent, tx.priority, written, "ops")
        preempted += self.claims.check(tx.agent, tx.priority, claim_keys, "claim")

        canonical = apply_ops(self.graph, tx.ops, tx.preconditions)  # raises, graph unchanged

        changes = self._claim_changes(tx, claim_keys, release_keys, preempted, canonical, now)
        volatile = not changes and only_volatile(self.graph, canonical)
        delta = self._commit(tx.agent, tx.id, canonical, changes, now, volatile)
        provenance.stamped(self.graph, canonical, delta["stamp"], delta["agent"])
        return delta

    def take_server_deltas(self) -> list[dict[str, Any]]:
        """The deltas the server committed of its own while taking requests since the last call
        (an ended run's info node marked gone), in seq order: broadcast before the request's."""
        deltas, self._server_deltas = self._server_deltas, []
        return deltas

    def _check_limits(self, tx) -> None:
        """The server's limits, each refusal naming the limit (the graph is not touched)."""
        if len(tx.ops) > self.max_ops:
            raise TransactionRejected(
                Violation(
                    "too-large",
                    "transaction",
                    f"{len(tx.ops)} operations exceed max_ops ({self.max_ops})",
                )
            )
        if tx.lease is not None and not tx.lease <= self.max_lease:
            raise TransactionRejected(
                Violation(
                    "lease",
                    "transaction",
                    f"a lease of {tx.lease} s exceeds max_lease ({self.max_lease} s)",
                    "claim",
                )
            )
        for i, op in enumerate(tx.ops):
            attrs = op.get("attrs")
            for name, value in attrs.items() if isinstance(attrs, dict) else ():
                size = declared_size(value)
                if size > self.max_value_bytes:
                    raise TransactionRejected(
                        Violation(
                            "too-large",
                            f"attribute {name!r}",
                            f"a value of {size} bytes exceeds max_value_bytes "
                            f"({self.max_value_bytes})",
                            f"op {i} ({op.get('op')})",
                        )
                    )
        added = sum(op.get("op") == "insert_node" for op in tx.ops)
        removed = sum(op.get("op") == "delete_node" for op in tx.ops)
        if added > removed and len(self.graph) + added - removed > self.max_nodes:
            raise TransactionRejected(
                Violation(
                    "too-large",
                    "transaction",
                    f"the graph would hold {len(self.graph) + added - removed} nodes, more than "
                    f"max_nodes ({self.max_nodes})",
                )
            )

    def _claim_changes(
        self,
        tx,
        claim_keys,
        release_keys,
        preempted: list[Claim],
        canonical: list[dict[str, Any]],
        now: float,
    ) -> dict[str, list[dict[str, Any]]]:
        ended: dict[tuple, dict[str, Any]] = {}
        for claim in preempted:
            ended[claim.key] = released(claim, "preempted", by=tx.agent)
        mine = self.claims.held_by(tx.agent) if tx.agent else []
        for claim in mine:
            if release_keys is None or claim.key in release_keys:
                ended.setdefault(claim.key, released(claim, "released"))
        deleted = [op["node"] for op in canonical if op["op"] == "delete_node"]
        for claim in self.claims.on_nodes(deleted):
            ended.setdefault(claim.key, released(claim, "node-deleted", by=tx.agent))
        expires = None if tx.lease is None else now + tx.lease
        granted = [Claim(key, tx.agent, tx.priority, expires).to_json() for key in claim_keys]
        changes: dict[str, list[dict[str, Any]]] = {}
        if ended:
            changes["released"] = list(ended.values())
        if granted:
            changes["granted"] = granted
        return changes

    def _commit(
        self,
        agent: str,
        ident: str,
        ops: list[dict[str, Any]],
        changes: dict[str, Any],
        now: float,
        volatile: bool = False,
    ) -> dict[str, Any]:
        self.claims.apply_changes(changes)
        delta: dict[str, Any]
        if volatile:  # follows the seq it was applied at, as a replica must be to apply it
            self.volatile_count += 1
            delta = {"seq": self.seq, VOLATILE: self.volatile_count}
        else:
            self.seq += 1
            delta = {"seq": self.seq}
        delta |= {"stamp": now, "agent": agent, "id": ident, "ops": ops}
        if changes:
            delta["claims"] = changes
        self._remember(ident, self.seq)
        return delta

    def _remember(self, ident: str, seq: int) -> None:
        if ident:
            self.accepted_ids[ident] = seq
            if len(self.accepted_ids) > REMEMBERED_IDS:
                self.accepted_ids.popitem(last=False)

    # ------------------------------------------------------------------ housekeeping
    def end_claims(
        self, claims: Iterable[Claim], reason: str, now: float | None = None
    ) -> dict[str, Any] | None:
        """A server delta ending these claims (lease expired, holder gone), or None."""
        records = [released(c, reason) for c in claims]
        if not records:
            return None
        return self._commit(
            SERVER_AGENT, "", [], {"released": records}, time.time() if now is None else now
        )

    def end_claims_of(
        self, agents: Iterable[str], reason: str, now: float | None = None
    ) -> dict[str, Any] | None:
        """A server delta ending every claim these agents hold (gone, out of reach), or None."""
        agents = set(agents)
        return self.end_claims([c for c in self.claims.all() if c.agent in agents], reason, now)

    def mark_gone(self, agents: Iterable[str], now: float | None = None) -> dict[str, Any] | None:
        """A server delta marking these agents' info nodes gone (model/agent_info.py): their
        processes ended. None when there is nothing to mark."""
        ops = gone_ops(self.graph, agents)
        if not ops:
            return None
        canonical = apply_ops(self.graph, ops)
        delta = self._commit(SERVER_AGENT, "", canonical, {}, time.time() if now is None else now)
        provenance.stamped(self.graph, canonical, delta["stamp"], delta["agent"])
        return delta

    # ------------------------------------------------------------------ replay and snapshots
    def replay(self, delta: dict[str, Any]) -> None:
        """Re-apply a journaled delta after a restart (it was valid when accepted)."""
        if delta.get("seq") != self.seq + 1:
            raise ValueError(
                f"journal out of order: expected seq {self.seq + 1}, found {delta.get('seq')!r}"
            )
        delta = resolve(delta, _no_bytes, lazy=True)  # sensor data's bytes: never held here
        ops = [without_absent_volatile(self.graph, op) for op in delta["ops"]]
        provenance.apply_delta(self.graph, delta, ops)
        self.claims.apply_changes(delta.get("claims", {}))
        self.seq = delta["seq"]
        self._remember(delta.get("id") or "", self.seq)

    def snapshot(self) -> dict[str, Any]:
        doc = dsr_json.to_json(self.graph, "snapshot", seq=self.seq)
        doc["claims"] = self.claims.to_json()
        return doc

    def durable_snapshot(self) -> dict[str, Any]:
        """The snapshot the server persists: also the ids of the latest accepted requests, so
        that after a restart a request sent again is still recognised."""
        doc = self.snapshot()
        doc["accepted_ids"] = [[i, s] for i, s in list(self.accepted_ids.items())[-SNAPSHOT_IDS:]]
        return doc

    @classmethod
    def restore(
        cls, snapshot: dict[str, Any], replay_journal, vocabulary=None, **kwargs: Any
    ) -> tuple[ServerCore, int, bool]:
        """The core a stored state gives: its snapshot, then ``replay_journal(seq, replay)``
        (``StateStore.replay_journal``). Returns (core, deltas replayed, converted): a state
        written before units were declared is in millimetres, journal included, and is
        converted to metres (store a new snapshot then, so it is converted once)."""
        core = cls.from_snapshot(snapshot, vocabulary, **kwargs)
        legacy = not units.declared(snapshot)
        per_metre = units.PER_METRE[units.LEGACY] if legacy else 1.0
        replayed = replay_journal(
            core.seq, lambda delta: core.replay(units.delta_in_metres(delta, per_metre))
        )
        return core, replayed, legacy

    @classmethod
    def from_snapshot(cls, doc: dict[str, Any], vocabulary=None, **kwargs: Any) -> ServerCore:
        doc = resolve(doc, _no_bytes, lazy=True)  # sensor data's bytes: never held here
        graph, seq = dsr_json.snapshot_from_json(doc, vocabulary)
        core = cls(graph, seq, ClaimTable.from_json(doc.get("claims", [])), **kwargs)
        for ident, accepted_at in doc.get("accepted_ids", []):
            core._remember(ident, accepted_at)
        return core


def _with_blobs(
    doc: dict[str, Any], blobs: Callable[[str], bytes | None], sensor: Container[str], agent: str
) -> dict[str, Any]:
    """The request with its blob references replaced by their values, or its rejection. The
    bytes of ``sensor`` attributes' values (sensor data) never come to the server: it keeps
    their reference (a ``BlobRef``: their digest, type, shape, and ``agent``, who holds them)."""
    writer = agent.rsplit("/", 1)[-1]
    try:
        return resolve(
            doc, blobs, lazy=sensor, held_at=writer if NODE_NAME.fullmatch(writer) else None
        )
    except MissingBlob as e:
        raise TransactionRejected(Violation("blob-missing", f"blob {e.digest}", str(e))) from None
    except ValueTypeError as e:
        raise TransactionRejected(Violation("malformed", "blob reference", str(e))) from None


def _no_bytes(digest: str) -> None:
    return None


def _id_of(doc: Any) -> str:
    """A request's id, "" when it has none (or is not an object)."""
    return doc["id"] if isinstance(doc, dict) and isinstance(doc.get("id"), str) else ""
