"""The agent's protocol (protocol/agent_core.py), the one DsrAgent and LocalAgent both run, over a
network that loses, repeats and reorders what the server sends, and a server that restarts from
its journal (ServerCore.restore), losing what was on its way to it. Whatever happens, once the
network heals: every request has exactly one verdict, each is applied once, an agent's requests
apply in the order it sent them, and every replica is the server's graph.

What the network may do to requests is what reliable DDS may: lose those in flight when the
server dies; a restart takes time (a new process), in which the agents see its subscription go
(as DDS tells them). A second property lets requests too be lost, repeated and reordered at
will: then only the order is not promised (nothing in a request says what came before it).

The server either journals a change before broadcasting it (as LocalBus: its deltas say nothing
of durability) or, as dsr_server, broadcasts it at once and makes it durable in a group commit
that the test runs when it chooses (formats/group_commit.py): a restart then loses what was
broadcast and not committed. Nothing acknowledged may be lost: every verdict is checked against
the durable journal the moment it is given."""

from __future__ import annotations

import json
from dataclasses import dataclass, field

import pytest
from hypothesis import HealthCheck, event, given, settings, target
from hypothesis import strategies as st

from dsr_graph.model.binary import dumps
from dsr_graph.model.graph import Graph
from dsr_graph.protocol.agent_core import DUPLICATE_PATIENCE, TICK, AgentCore
from dsr_graph.protocol.server_core import Rejection, ServerCore

pytestmark = pytest.mark.unit

AGENTS = ("/speech", "/panel")
HEAL_LIMIT = 120.0  # virtual seconds a healed network has to settle everything


@dataclass
class Message:
    to: str  # an agent's name, or "server"
    kind: str  # request | delta | rejection | heartbeat | snapshot
    text: str
    sender: str = ""
    asked: int = 0  # a snapshot's request number (an answer to a withdrawn one is not given)


@dataclass
class Net:
    """The server's core and the messages on their way, which the test delivers in its order."""

    requests_faulty: bool = False
    group_commit: bool = False
    now: float = 0.0
    up: bool = True
    boot: int = 0
    flight: list[Message] = field(default_factory=list)
    journal: list[dict] = field(default_factory=list)  # durable
    buffer: list[dict] = field(default_factory=list)  # broadcast, not yet durable
    cores: dict[str, AgentCore] = field(default_factory=dict)
    asked: dict[str, int] = field(default_factory=dict)
    beat_at: float = 0.0

    def __post_init__(self) -> None:
        self.start = ServerCore(Graph()).snapshot()
        self.server = ServerCore.from_snapshot(self.start)

    # -------------------------------------------------------------- the server
    def restart(self) -> None:
        """The server dies: what was on its way to it is lost; it comes back from its journal
        after a second in which the agents see it gone."""
        self.up = False
        self.flight = [m for m in self.flight if m.to != "server"]
        self.buffer = []  # killed between broadcast and commit
        self.advance(1.0)
        self.server, _, _ = ServerCore.restore(
            self.start,
            lambda seq, replay: sum(replay(d) is None for d in self.journal if d["seq"] > seq),
        )
        self.up = True
        self.boot += 1
        self.beat()

    @property
    def durable(self) -> int:
        return self.journal[-1]["seq"] if self.journal else 0

    def beat(self) -> None:
        beat = {"seq": self.server.seq, "boot": f"b{self.boot}", "unreachable": []}
        if self.group_commit:
            beat["durable"] = self.durable
        text = json.dumps(beat)
        for name in self.cores:
            self.flight.append(Message(name, "heartbeat", text))
        self.beat_at = self.now

    def commit(self) -> None:
        """The group commit: what was broadcast is durable, and the agents are told."""
        if not self.up or not self.buffer:
            return
        self.journal += self.buffer
        self.buffer = []
        text = json.dumps({"boot": f"b{self.boot}", "durable": self.durable})
        for name in self.cores:
            self.flight.append(Message(name, "durable", text))

    def serve(self, message: Message) -> None:
        if not self.up:
            return
        if message.kind == "snapshot":  # a request for one, answered to its asker
            text = dumps(self.server.snapshot())
            self.flight.append(Message(message.sender, "snapshot", text, asked=message.asked))
            return
        result = self.server.submit(message.text, now=self.now, sender=message.sender)
        if isinstance(result, Rejection):
            text = dumps(result.to_json())
            self.flight.append(Message(message.sender, "rejection", text))
            return
        delta = json.loads(dumps(result))
        if self.group_commit:
            self.buffer.append(delta)
            delta = {**delta, "boot": f"b{self.boot}", "durable": self.durable}
        else:
            self.journal.append(delta)
        for name in self.cores:
            self.flight.append(Message(name, "delta", dumps(delta)))

    # -------------------------------------------------------------- delivery and time
    def deliver(self, index: int) -> None:
        message = self.flight.pop(index % len(self.flight))
        if message.to == "server":
            self.serve(message)
            return
        core = self.cores[message.to]
        if message.kind == "delta":
            core.on_delta(message.text, self.now)
        elif message.kind == "rejection":
            core.on_rejection(message.text, self.now)
        elif message.kind == "heartbeat":
            core.on_heartbeat(message.text, self.now)
        elif message.kind == "durable":
            core.on_durable(message.text, self.now)
        elif message.asked == self.asked[message.to]:
            core.on_snapshot(message.text, self.now)

    def advance(self, seconds: float) -> None:
        end = self.now + seconds
        while self.now < end:
            self.now = min(end, self.now + TICK)
            if self.up and self.now - self.beat_at >= 1.0:
                self.beat()
            for core in self.cores.values():
                core.tick(self.now)


class NetLink:
    def __init__(self, net: Net, name: str):
        self.net, self.name = net, name

    def publish(self, text: str, blobs: dict[str, bytes]) -> None:
        self.net.flight.append(Message("server", "request", text, sender=self.name))

    def matched(self) -> bool:
        return self.net.up

    def ask_snapshot(self) -> None:
        self.net.asked[self.name] += 1
        asked = self.net.asked[self.name]
        self.net.flight.append(Message("server", "snapshot", "", sender=self.name, asked=asked))

    def withdraw_snapshot(self) -> None:
        self.net.asked[self.name] += 1

    def log(self, level: str, message: str) -> None:
        pass


def network(requests_faulty: bool, group_commit: bool = False) -> tuple[Net, dict[str, list]]:
    net = Net(requests_faulty=requests_faulty, group_commit=group_commit)
    verdicts: dict[str, list] = {}
    for name in AGENTS:
        net.asked[name] = 0
        net.cores[name] = AgentCore(name, NetLink(net, name), run="r")
        net.cores[name].ask_snapshot(net.now)
    net.beat()
    return net, verdicts


ACTIONS = st.lists(
    st.one_of(
        st.tuples(st.just("send"), st.sampled_from(AGENTS)),
        st.tuples(st.just("deliver"), st.integers(0, 50)),
        st.tuples(st.just("drop"), st.integers(0, 50)),
        st.tuples(st.just("repeat"), st.integers(0, 50)),
        st.tuples(st.just("wait"), st.sampled_from([0.1, 0.5, 1.0, 3.5])),
        st.tuples(st.just("restart"), st.none()),
        st.tuples(st.just("commit"), st.none()),
    ),
    max_size=60,
)


def verdict_to(net: Net, verdicts: dict[str, list]):
    """A verdict callback that checks an accepted change is durable when its writer hears."""

    def given(result) -> None:
        if result.accepted:
            assert result.id in {d["id"] for d in net.journal}, f"{result.id}: not durable"
        verdicts.setdefault(result.id, []).append(result)

    return given


def play(net: Net, verdicts: dict[str, list], actions, sent: dict[str, list[str]]) -> None:
    for kind, arg in actions:
        if kind == "send":
            name = f"n{sum(len(v) for v in sent.values())}"
            ident = net.cores[arg].send(
                {"ops": [{"op": "insert_node", "name": name, "type": "cup"}]},
                verdict_to(net, verdicts),
                net.now,
            )
            sent[arg].append(ident)
        elif kind == "restart":
            net.restart()
        elif kind == "commit":
            net.commit()
        elif kind == "wait":
            net.advance(arg)
        elif net.flight:
            index = arg % len(net.flight)
            faulty = net.requests_faulty or net.flight[index].to != "server"
            if kind == "deliver" and faulty:
                net.deliver(index)  # any message, out of order
            elif kind == "deliver":
                net.deliver(_first_request(net))  # requests stay in the order they were sent
            elif kind == "drop" and faulty:
                net.flight.pop(index)
            elif kind == "repeat" and faulty:
                net.flight.append(net.flight[index])


def _first_request(net: Net) -> int:
    return next(i for i, m in enumerate(net.flight) if m.to == "server")


def heal(net: Net, verdicts: dict[str, list], sent: dict[str, list[str]]) -> None:
    """Deliver everything in order, with time passing, until all is settled."""
    expected = {i for ids in sent.values() for i in ids}
    while net.now < HEAL_LIMIT:
        net.commit()
        while net.flight:
            net.deliver(0)
        settled = all(c.replica.seq == net.server.seq and not c.busy for c in net.cores.values())
        if settled and expected <= set(verdicts):
            return
        net.advance(TICK)


def check(net: Net, verdicts: dict[str, list], sent: dict[str, list[str]], ordered: bool) -> None:
    journal_ids = [d["id"] for d in net.journal]
    assert len(journal_ids) == len(set(journal_ids)), "a request was applied twice"
    for name, ids in sent.items():
        for ident in ids:
            assert len(verdicts.get(ident, [])) == 1, f"{ident}: {verdicts.get(ident)}"
            assert verdicts[ident][0].accepted, verdicts[ident][0].error
        assert set(ids) <= set(journal_ids)
        if ordered:
            applied = [i for i in journal_ids if i in set(ids)]
            assert applied == ids, f"{name}'s requests applied out of order"
    target(float(sum(c.resyncs for c in net.cores.values())), label="resyncs")
    event(f"resynchronised after a loss: {any(c.resyncs > 1 for c in net.cores.values())}")
    event(f"server restarted: {net.boot > 0}")
    event(f"group commit: {net.group_commit}")
    names = sorted(n.name for n in net.server.graph.nodes())
    for core in net.cores.values():
        assert core.replica.seq == net.server.seq
        assert sorted(n.name for n in core.graph.nodes()) == names


@pytest.mark.parametrize("group_commit", [False, True], ids=["durable-first", "group-commit"])
@pytest.mark.parametrize(
    "requests_faulty", [False, True], ids=["requests-in-order", "requests-lost-and-reordered"]
)
@settings(max_examples=200, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(actions=ACTIONS)
def test_exactly_once_whatever_the_network_and_the_server_go_through(
    requests_faulty, group_commit, actions
):
    """In order too, unless requests themselves are lost and reordered; with a group commit, a
    restart between broadcast and commit loses nothing acknowledged and every replica that saw
    what was lost comes back to the server's graph."""
    net, verdicts = network(requests_faulty, group_commit)
    sent = {name: [] for name in AGENTS}
    play(net, verdicts, actions, sent)
    heal(net, verdicts, sent)
    check(net, verdicts, sent, ordered=not requests_faulty)


def test_a_request_the_server_already_applied_is_answered_once_the_replica_has_it():
    """Its delta lost, its repeat called a duplicate: the verdict comes with the resync."""
    net, verdicts = network(requests_faulty=False)
    while net.flight:
        net.deliver(0)
    speech = net.cores["/speech"]
    ident = speech.send(
        {"ops": [{"op": "insert_node", "name": "cup", "type": "cup"}]},
        lambda result: verdicts.setdefault(result.id, []).append(result),
        net.now,
    )
    net.deliver(_first_request(net))
    net.flight = [m for m in net.flight if m.to != "/speech"]  # its delta never comes
    net.advance(3.5)  # resent, answered "duplicate_of"
    assert ident not in verdicts
    heal(net, verdicts, {"/speech": [ident]})
    assert [v.accepted for v in verdicts[ident]] == [True]
    assert verdicts[ident][0].seq == 1 and "cup" in speech.graph


@pytest.mark.parametrize("lost", [False, True])
def test_an_idle_replica_told_the_server_is_ahead_waits_for_the_delta_on_its_way(lost):
    """Idle for seconds, then a heartbeat overtakes a delta: the replica is behind, not stalled,
    and asks for no snapshot unless the delta stays away for GAP_PATIENCE (lost)."""
    net, verdicts = network(requests_faulty=False)
    while net.flight:
        net.deliver(0)
    net.advance(5.0)  # idle: heartbeats only
    while net.flight:
        net.deliver(0)
    panel, speech = net.cores["/panel"], net.cores["/speech"]
    panel.send({"ops": [{"op": "insert_node", "name": "cup", "type": "cup"}]}, None, net.now)
    net.deliver(_first_request(net))
    net.beat()  # the server's heartbeat reaches /speech before its delta
    beat = next(i for i, m in enumerate(net.flight) if m.to == "/speech" and m.kind == "heartbeat")
    net.deliver(beat)
    asked = net.asked["/speech"]
    speech.tick(net.now + TICK)
    assert net.asked["/speech"] == asked  # behind, not stalled
    delta = next(i for i, m in enumerate(net.flight) if m.to == "/speech" and m.kind == "delta")
    if lost:
        net.flight.pop(delta)
        for step in range(1, 10):
            speech.tick(net.now + step * TICK)
        assert net.asked["/speech"] == asked + 1  # GAP_PATIENCE without it: a snapshot
    else:
        net.deliver(delta)
        speech.tick(net.now + 2 * TICK)
        assert net.asked["/speech"] == asked and "cup" in speech.graph


def test_a_request_a_snapshot_took_is_answered_without_waiting_for_its_resend():
    """After a server restart, /speech resyncs; its next request is applied before the server
    answers its snapshot, so the snapshot holds that request's delta, which the replica never
    applies one by one. Its verdict comes soon after the snapshot, not RESEND_AFTER (3 s) later:
    every agent's first write after a restart (its info node's "ready" among them) waited that
    long, and PELEA waited for it."""
    net, verdicts = network(requests_faulty=False, group_commit=True)
    speech = net.cores["/speech"]

    def deliver(kind: str, to: str) -> None:
        net.deliver(next(i for i, m in enumerate(net.flight) if m.kind == kind and m.to == to))

    while net.flight:
        net.deliver(0)
    net.cores["/panel"].send({"ops": [{"op": "insert_node", "name": "a", "type": "cup"}]}, None, 0)
    while net.flight:  # broadcast, never committed: both replicas ahead of the restarted server
        net.deliver(0)
    net.restart()
    deliver("heartbeat", "/speech")  # a new boot: /speech resyncs
    while not any(m.kind == "snapshot" and m.to == "server" for m in net.flight):
        net.advance(TICK)
    ident = speech.send(
        {"ops": [{"op": "insert_node", "name": "b", "type": "cup"}]},
        lambda result: verdicts.setdefault(result.id, []).append(result),
        net.now,
    )
    request = next(i for i, m in enumerate(net.flight) if m.text and ident in m.text)
    net.deliver(request)  # applied before the snapshot is made
    deliver("snapshot", "server")
    deliver("delta", "/speech")  # while the snapshot is awaited
    deliver("snapshot", "/speech")
    net.commit()
    sent_at = net.now
    while ident not in verdicts and net.now - sent_at < 3.0:
        while net.flight:
            net.deliver(0)
        net.advance(TICK)
    assert [v.accepted for v in verdicts.get(ident, [])] == [True]
    # the server calls the repeat a duplicate; its delta is not awaited beyond DUPLICATE_PATIENCE
    took = net.now - sent_at
    assert took <= DUPLICATE_PATIENCE + 2 * TICK, f"the verdict took {took:.2f} s"
    assert "b" in speech.graph
