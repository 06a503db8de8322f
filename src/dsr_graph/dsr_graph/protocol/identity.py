"""Who sent a request, as the ROS graph shows it (pure; the server feeds it what
``get_publishers_info_by_topic`` says). The middleware gives no sender with a message (rclpy's
message info has no publisher GID), so each agent has a request topic of its own,
``dsr/transactions/<node name>``, and a request on it is the named node's only while the ROS
graph shows that node as the topic's one and only publisher. The old shared
``dsr/transactions`` is attributed only while exactly one node publishes on it.

Without DDS security (docs: the wheels' Fast DDS has no security plugins) a process can still
start a node under a name no other node uses, and be taken for it: identity here stops one node
from writing as another that is running, not an impostor of a node that is not.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

from dsr_graph.protocol.topic_names import PRESENCE, TRANSACTIONS


@dataclass(frozen=True)
class Publisher:
    namespace: str
    name: str
    participant: bytes = b""  # the DDS participant (GUID prefix): one per process's context

    @property
    def fqn(self) -> str:
        return f"{self.namespace.rstrip('/')}/{self.name}"


@dataclass(frozen=True)
class Sender:
    """The verdict on a request topic: the node proven to be its sender, or why none is."""

    agent: str | None
    problem: str = ""
    intruders: tuple[str, ...] = ()
    # seconds the verdict may be waited for from a request's arrival (0: final): a publisher's
    # node not known yet, or a killed node not gone yet
    pending: float = 0.0


UNKNOWN = "_NODE_NAME_UNKNOWN_"  # rmw's name for a participant whose node info has not arrived
NODE_NOT_KNOWN = "has a publisher whose node is not known yet"  # the refusal's words for it
# Node names come on rmw's ros_discovery_info, a reliable transient-local topic apart from DDS's
# own endpoint discovery: a first sample lost is sent again at its writer's next heartbeat, every
# 3 s by Fast DDS's default. Seen in CI after a server's restart: more than 3 s. Three heartbeats.
NODE_INFO_WAIT = 10.0
# A node killed outright stays listed until its DDS lease (2 s, config/fastdds_profile.xml) runs
# out, beside its restarted self.
LEASE_WAIT = 3.0


def agent_topic(node_name: str) -> str:
    """The request topic of the node called ``node_name`` (relative, like the others)."""
    return f"{TRANSACTIONS}/{node_name}"


def presence_topic(node_name: str) -> str:
    """The topic whose liveliness tells that the node called ``node_name`` is in reach."""
    return f"{PRESENCE}/{node_name}"


def sender_on(
    topic: str,
    owner: str | None,
    publishers: Sequence[Publisher],
    liveliness: tuple[int, int] | None = None,
    matched: int | None = None,
) -> Sender:
    """``owner``: the node name a per-agent topic belongs to; None for the shared topic.
    ``liveliness``: (alive, matched but not alive) of the topic's publishers that offer the
    agents' liveliness lease, as DDS last counted them (protocol/presence.py); None: unknown.
    ``matched``: how many publishers the request subscription has matched (DDS's own count);
    None: unknown."""
    if any(p.name == UNKNOWN for p in publishers):
        # DDS found the publisher before the ROS graph learnt its node (typically just after
        # a restart): not a verdict yet
        return Sender(None, f"{topic} {NODE_NOT_KNOWN}", pending=NODE_INFO_WAIT)
    if matched is not None and matched > len(publishers):
        # DDS matched a publisher the ROS graph does not list yet (its discovery reaches the
        # graph after the match, seen on a loaded machine): it may be this request's sender, so
        # the owner alone in the graph proves nothing yet
        return Sender(
            None,
            f"{topic} has {matched} matched publishers but the ROS graph lists "
            f"{len(publishers)}: one is not known yet",
            pending=NODE_INFO_WAIT,
        )
    # one node may publish through several endpoints (two DsrAgents in one node): what counts
    # is how many nodes publish, told apart by name and by DDS participant
    nodes = sorted({(p.fqn, p.participant): p for p in publishers}.values(), key=_order)
    names = ", ".join(p.fqn for p in nodes) or "none"
    if owner is None:
        if len(nodes) == 1:
            return Sender(nodes[0].fqn)
        return Sender(
            None,
            f"{topic} has {len(nodes)} publishing nodes ({names}): a request on it cannot be "
            "told from another's; publish on dsr/transactions/<your node name>",
        )
    owners = [p for p in nodes if p.name == owner]
    intruders = tuple(sorted({p.fqn for p in nodes if p.name != owner}))
    if len(nodes) == 1 and owners:
        return Sender(owners[0].fqn)
    if intruders:
        return Sender(
            None,
            f"{topic} belongs to the node named {owner!r}, but {', '.join(intruders)} "
            f"publish{'es' if len(intruders) == 1 else ''} on it (publishers: {names}): "
            "its requests are refused until only its owner publishes",
            intruders,
        )
    # Two participants under the owner's name: a node killed outright stays listed until its
    # DDS lease runs out, next to its restarted self. Its presence publisher's liveliness lapses
    # sooner (PRESENCE_LEASE): when every one of them is counted and only one is alive, that one
    # is the successor, and the only one that can be sending (a frozen twin that wakes is alive
    # again, and the verdict is asked again).
    if successor_known(owners, publishers, liveliness):
        return Sender(owners[0].fqn)
    # Otherwise not a verdict yet; if it lasts (the server's hold), two live nodes share the
    # name and neither can be told from the other.
    return Sender(
        None,
        f"{topic} has {len(nodes)} publishing nodes named {owner!r} ({names}): "
        "two nodes share that name (or one of them died and is not gone yet)",
        tuple(sorted({p.fqn for p in owners})),
        pending=LEASE_WAIT,
    )


def successor_known(
    owners: Sequence[Publisher],
    publishers: Sequence[Publisher],
    liveliness: tuple[int, int] | None,
) -> bool:
    """Of the owner's nodes (one endpoint each, all of them watched for liveliness), exactly one
    is alive: the others are a killed, frozen or cut-off predecessor."""
    if liveliness is None or len(publishers) != len(owners):  # one endpoint a node
        return False
    if len({p.fqn for p in owners}) != 1:  # /speech and /b/speech: which one is alive?
        return False
    alive, not_alive = liveliness
    return alive == 1 and alive + not_alive == len(owners)


def _order(p: Publisher) -> tuple[str, bytes]:
    return (p.fqn, p.participant)
