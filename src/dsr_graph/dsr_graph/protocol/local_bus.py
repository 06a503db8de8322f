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
import logging
from collections import deque
from collections.abc import Callable
from typing import Any

from dsr_graph.exceptions import TimedOutError
from dsr_graph.model.binary import compact, dumps
from dsr_graph.model.graph import Graph
from dsr_graph.model.policy import OPEN, Policy
from dsr_graph.protocol.agent_core import TICK, AgentCore, Listener
from dsr_graph.protocol.presence import PRESENCE_LEASE
from dsr_graph.protocol.replica import Replica
from dsr_graph.protocol.server_core import Rejection, Result, ServerCore

LOG = logging.getLogger(__name__)
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
        agent.core.on_snapshot(self.snapshot_text(), self.now)
        self.agents.append(agent)
        return agent

    # ------------------------------------------------------------------ the server's side
    def snapshot_text(self) -> str:
        return dumps(self.core.snapshot())

    def submit(self, sender: LocalAgent, text: str, blobs: dict[str, bytes]) -> None:
        """A request's text (and the bytes of the binary values it references), as sent."""
        result = self.core.submit(text, now=self.now, sender=sender.name, blobs=blobs.get)
        for delta in self.core.take_server_deltas():  # committed before the request's
            self.broadcast(delta)
        if isinstance(result, Rejection):  # to the sender only: the others ignore it
            wire = dumps(result.to_json())
            self.soon(lambda: sender.rejected(wire))
            return
        self.broadcast(result)

    def broadcast(self, delta: dict[str, Any]) -> None:
        wire = compact(delta)
        for agent in list(self.agents):
            self.soon(lambda agent=agent: agent.receive(wire))

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
                self.broadcast(delta)

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

    def _arm_ticks(self) -> None:
        """An agent waiting for something (a verdict during a cut, a delta's duplicate) ticks,
        as DsrAgent's timer does; an idle one does not, so a run with nothing to do ends."""
        for agent in self.agents:
            if not agent.closed and not agent.ticking and agent.core.busy:
                agent.ticking = True
                self.after(TICK, agent.tick)

    def run(self, until: Callable[[], bool] = lambda: False, limit: float = 3600.0) -> float:
        """Deliver, then advance the clock to the next timer, until ``until()`` holds or nothing
        is left to do; ``TimedOutError`` if ``limit`` virtual seconds pass first. The virtual
        time it took."""
        start = self.now
        while True:
            self.deliver()
            self._arm_ticks()
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
    """An agent's link to a ``LocalBus``: what ``dsr_graph.ros.agent.DsrAgent`` is over ROS, with
    the same protocol (``agent_core.py``); the bus's "network" never loses a message."""

    def __init__(self, bus: LocalBus, name: str, run: int = 0):
        self.bus = bus
        self.name = name
        self.core = AgentCore(name, self, str(run), vocabulary=bus.core.graph.vocabulary)
        self.closed = False
        self.cut = False
        self.ticking = False  # a tick is on the bus's clock
        self._snapshots = 0  # snapshot requests made: an answer to an older one is not given
        self._held_in: list[Callable[[], None]] = []  # what reached the cut, for this agent
        self._held_out: list[tuple[str, dict[str, bytes]]] = []  # what it sent during a cut

    @property
    def replica(self) -> Replica:
        return self.core.replica

    @property
    def graph(self) -> Graph:
        return self.core.graph

    @property
    def synced(self) -> bool:
        return self.core.synced

    def add_listener(self, listener: Listener) -> None:
        self.core.add_listener(listener)

    def send(self, doc: dict[str, Any], on_done: Callable[[Result], None] | None = None) -> str:
        return self.core.send(doc, on_done, self.bus.now)

    def close(self) -> None:
        """The agent's process died: nothing reaches it any more and nothing it sends arrives."""
        self.closed = True
        self.core.close()

    def mend(self) -> None:
        self.cut = False
        held_in, self._held_in = self._held_in, []
        held_out, self._held_out = self._held_out, []
        for deliver in held_in:
            self.bus.soon(deliver)
        for text, blobs in held_out:
            self.bus.soon(lambda text=text, blobs=blobs: self.bus.submit(self, text, blobs))

    def tick(self) -> None:
        self.ticking = False
        self.core.tick(self.bus.now)

    # ------------------------------------------------------------------ what the bus brings
    def _arrive(self, deliver: Callable[[], None]) -> None:
        if self.closed:
            return
        if self.cut:
            self._held_in.append(lambda: self._arrive(deliver))
            return
        deliver()

    def receive(self, text: str) -> None:
        """A delta's text."""
        self._arrive(lambda: self.core.on_delta(text, self.bus.now))

    def rejected(self, text: str) -> None:
        """A rejection's text: refused, or accepted earlier (``duplicate_of``)."""
        self._arrive(lambda: self.core.on_rejection(text, self.bus.now))

    # ------------------------------------------------------------------ the core's link
    def publish(self, text: str, blobs: dict[str, bytes]) -> None:
        if self.closed:
            return
        if self.cut:
            self._held_out.append((text, blobs))
        else:
            self.bus.submit(self, text, blobs)

    def matched(self) -> bool:
        return True

    def ask_snapshot(self) -> None:
        self._snapshots += 1
        asked = self._snapshots

        def answer() -> None:
            if asked == self._snapshots:
                self.core.on_snapshot(self.bus.snapshot_text(), self.bus.now)

        self.bus.soon(lambda: self._arrive(answer))

    def withdraw_snapshot(self) -> None:
        self._snapshots += 1

    def log(self, level: str, message: str) -> None:
        getattr(LOG, level)(f"{self.name}: {message}")
