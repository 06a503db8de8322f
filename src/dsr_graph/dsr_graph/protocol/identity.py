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

from dsr_graph.protocol.topic_names import TRANSACTIONS


@dataclass(frozen=True)
class Publisher:
    namespace: str
    name: str

    @property
    def fqn(self) -> str:
        return f"{self.namespace.rstrip('/')}/{self.name}"


@dataclass(frozen=True)
class Sender:
    """The verdict on a request topic: the node proven to be its sender, or why none is."""

    agent: str | None
    problem: str = ""
    intruders: tuple[str, ...] = ()


def agent_topic(node_name: str) -> str:
    """The request topic of the node called ``node_name`` (relative, like the others)."""
    return f"{TRANSACTIONS}/{node_name}"


def sender_on(topic: str, owner: str | None, publishers: Sequence[Publisher]) -> Sender:
    """``owner``: the node name a per-agent topic belongs to; None for the shared topic."""
    names = ", ".join(sorted(p.fqn for p in publishers)) or "none"
    if owner is None:
        if len(publishers) == 1:
            return Sender(publishers[0].fqn)
        return Sender(
            None,
            f"{topic} has {len(publishers)} publishers ({names}): a request on it cannot be "
            "told from another's; publish on dsr/transactions/<your node name>",
        )
    owners = [p for p in publishers if p.name == owner]
    intruders = tuple(sorted(p.fqn for p in publishers if p.name != owner))
    if len(publishers) == 1 and owners:
        return Sender(owners[0].fqn)
    if intruders:
        return Sender(
            None,
            f"{topic} belongs to the node named {owner!r}, but {', '.join(intruders)} "
            f"publish{'es' if len(intruders) == 1 else ''} on it (publishers: {names}): "
            "its requests are refused until only its owner publishes",
            intruders,
        )
    return Sender(
        None,
        f"{topic} has {len(publishers)} publishers named {owner!r} ({names}): "
        "two nodes share that name, so neither can be told from the other",
        tuple(sorted(p.fqn for p in owners)),
    )
