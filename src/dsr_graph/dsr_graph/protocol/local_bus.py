"""A DSR in one process, on virtual time: the server's core and any number of agents, each with
its own replica, exchanging the same JSON text as over ROS, in the same order (deltas in seq
order to every agent; a verdict to the sender once its replica applied the delta, or the
rejection). Deliveries are queued and run one at a time, as an executor runs callbacks, so a
callback never runs inside another. Timers run on a virtual clock, so a test that waits minutes
of a real session takes milliseconds. Pure: for unit tests of rules, agents and PELEA, and for
simulations.

    bus = LocalBus(graph)
    speech = bus.agent("/speech")               # send, add_listener, graph, synced, name
    bus.after(2.0, lambda: ...)                 # a timer on the virtual clock
    bus.run(until=lambda: done, limit=600.0)    # deliver and advance time until done
    bus.cut(["/speech"]); bus.mend(["/speech"]) # a network cut: what crosses it is held

A cut holds what the agents on the far side send and what is sent to them, as DDS does for
reliable streams, and delivers it in order when it ends; the server counts them out of reach a
liveliness lease after it began (``presence.py``), and ends their claims (``unreachable``).
"""

from __future__ import annotations

import heapq
import itertools
import json
from collections import deque
from collections.abc import Callable
from typing import Any

from dsr_graph.exceptions import TimedOutError
from dsr_graph.model.binary import dumps
from dsr_graph.model.graph import Graph
from dsr_graph.model.policy import OPEN, Policy
from dsr_graph.protocol.presence import PRESENCE_LEASE
from dsr_graph.protocol.replica import Replica
from dsr_graph.protocol.server_core import Rejection, Result, ServerCore
from dsr_graph.protocol.volatility import is_volatile

Listener = Callable[[list[dict[str, Any]], bool], None]
MAX_DELIVERIES = 1_000_000  # per run: more means agents answer each other forever


class LocalTimer:
    def __init__(self) -> None:
        self.cancelled = False

    def cancel(self) -> None:
        self.cancelled = True


class LocalBus:
    def __init__(self, graph: Graph, start_time: float = 0.0, policy: Policy = OPEN):
        self.core = ServerCore(graph, policy=policy)
        self.agents: list[LocalAgent] = []
        self.now = start_time
        self._queue: deque[Callable[[], None]] = deque()
        self._timers: list[tuple[float, int, LocalTimer, Callable[[], None]]] = []
        self._order = itertools.count()
        self.unreachable: set[str] = set()  # agents the server counts out of reach
        self.reach_losses = 0  # how often an agent went out of reach (as the heartbeat tells)

    def agent(self, name: str) -> LocalAgent:
        """A new agent, synced with the graph as it is now."""
        agent = LocalAgent(self, name, run=len(self.agents))
        agent.replica.load_snapshot(json.loads(dumps(self.core.snapshot())))
        self.agents.append(agent)
        return agent

    # ------------------------------------------------------------------ the server's side
    def submit(self, sender: LocalAgent, doc: dict[str, Any]) -> None:
        result = self.core.submit(dumps(doc), now=self.now, sender=sender.name)
        if isinstance(result, Rejection) and result.duplicate_of is not None:
            verdict = Result(result.id, True, delta={"seq": result.duplicate_of, "id": result.id})
            self.soon(lambda: sender.rejected(verdict))
            return
        if isinstance(result, Rejection):
            verdict = Result(
                result.id, False, reason=result.violation.to_json(), error=str(result.violation)
            )
            self.soon(lambda: sender.rejected(verdict))
            return
        wire = dumps(result)
        for agent in list(self.agents):
            self.soon(lambda agent=agent: agent.receive(json.loads(wire)))

    # ------------------------------------------------------------------ network cuts
    def cut(self, names: list[str], detect: float = PRESENCE_LEASE) -> None:
        """The link to these agents goes down: they are told out of reach ``detect`` s later."""
        cut = [a for a in self.agents if a.name in names and not a.closed]
        for agent in cut:
            agent.cut = True

        def told() -> None:
            away = {a.name for a in cut if a.cut} - self.unreachable
            if not away:
                return
            self.unreachable |= away
            self.reach_losses += 1
            delta = self.core.end_claims_of(away, "unreachable", self.now)
            if delta is not None:
                wire = dumps(delta)
                for agent in list(self.agents):
                    self.soon(lambda agent=agent: agent.receive(json.loads(wire)))

        self.after(detect, told)

    def mend(self, names: list[str]) -> None:
        """The link is back: what was held crosses it, in order."""
        self.unreachable -= set(names)
        for agent in self.agents:
            if agent.name in names and agent.cut:
                agent.mend()

    # ------------------------------------------------------------------ time and deliveries
    def soon(self, callback: Callable[[], None]) -> None:
        """Run ``callback`` after everything already queued."""
        self._queue.append(callback)

    def after(self, seconds: float, callback: Callable[[], None]) -> LocalTimer:
        """Run ``callback`` when the virtual clock has advanced ``seconds``."""
        timer = LocalTimer()
        heapq.heappush(
            self._timers, (self.now + max(seconds, 0.0), next(self._order), timer, callback)
        )
        return timer

    def deliver(self) -> int:
        """Run queued deliveries until none is left (time does not advance); how many ran."""
        count = 0
        while self._queue:
            count += 1
            if count > MAX_DELIVERIES:
                raise RuntimeError(f"more than {MAX_DELIVERIES} deliveries without rest")
            self._queue.popleft()()
        return count

    def run(self, until: Callable[[], bool] = lambda: False, limit: float = 3600.0) -> float:
        """Deliver, then advance the clock to the next timer, until ``until()`` holds or nothing
        is left to do; ``TimedOutError`` if ``limit`` virtual seconds pass first. The virtual
        time it took."""
        start = self.now
        while True:
            self.deliver()
            if until():
                return self.now - start
            while self._timers and self._timers[0][2].cancelled:
                heapq.heappop(self._timers)
            if not self._timers:
                return self.now - start
            when, _, timer, callback = heapq.heappop(self._timers)
            if when - start > limit:
                heapq.heappush(self._timers, (when, next(self._order), timer, callback))
                raise TimedOutError(f"not done after {limit} s of virtual time")
            self.now = max(self.now, when)
            callback()


class LocalAgent:
    """An agent's link to a ``LocalBus``: what ``dsr_graph.ros.agent.DsrAgent`` is over ROS."""

    def __init__(self, bus: LocalBus, name: str, run: int = 0):
        self.bus = bus
        self.name = name
        self.run = run  # tells this agent's requests from those of an earlier one of that name
        self.replica = Replica(bus.core.graph.vocabulary)
        self._listeners: list[Listener] = []
        self._pending: dict[str, Callable[[Result], None] | None] = {}
        self._count = 0
        self.closed = False
        self.cut = False
        self._held_in: list[Callable[[], None]] = []  # what reached the cut, for this agent
        self._held_out: list[dict[str, Any]] = []  # what this agent sent during a cut

    @property
    def graph(self) -> Graph:
        return self.replica.graph

    @property
    def synced(self) -> bool:
        return self.replica.synced

    def add_listener(self, listener: Listener) -> None:
        self._listeners.append(listener)

    def close(self) -> None:
        """The agent's process died: nothing reaches it any more and nothing it sends arrives."""
        self.closed = True
        self._listeners.clear()
        self._pending.clear()

    def mend(self) -> None:
        self.cut = False
        held_in, self._held_in = self._held_in, []
        held_out, self._held_out = self._held_out, []
        for deliver in held_in:
            self.bus.soon(deliver)
        for doc in held_out:
            self.bus.soon(lambda doc=doc: self.bus.submit(self, doc))

    def send(self, doc: dict[str, Any], on_done: Callable[[Result], None] | None = None) -> str:
        if self.closed:
            return ""
        doc = dict(doc)
        doc.setdefault("agent", self.name)
        self._count += 1
        doc.setdefault("id", f"{self.name}:{self.run}:{self._count}")
        self._pending[doc["id"]] = on_done
        if self.cut:
            self._held_out.append(doc)
        else:
            self.bus.submit(self, doc)
        return doc["id"]

    def receive(self, delta: dict[str, Any]) -> None:
        if self.closed:
            return
        if self.cut:
            self._held_in.append(lambda: self.receive(delta))
            return
        applied = self.replica.receive(delta)
        if applied:
            for listener in list(self._listeners):
                listener(applied, False)
        if not applied and is_volatile(delta):  # skipped here, accepted all the same
            applied = [delta]
        for done in applied:
            callback = self._pending.pop(done.get("id"), None)
            if callback is not None:
                callback(Result(done["id"], True, delta=done))

    def rejected(self, verdict: Result) -> None:
        """The verdict of a request that made no new delta: refused, or accepted earlier."""
        if self.cut:
            self._held_in.append(lambda: self.rejected(verdict))
            return
        callback = self._pending.pop(verdict.id, None)
        if callback is not None:
            callback(verdict)
