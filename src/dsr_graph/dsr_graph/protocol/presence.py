"""Which agents the server can hear right now (pure; the server feeds it DDS liveliness).

An agent's presence publisher, on ``dsr/presence/<node name>``, offers a short DDS liveliness
lease (``PRESENCE_LEASE``, asserted by the middleware itself, not by the agent's Python) and
publishes only one empty message each time a server's watch matches it (counted alive at once,
not at the middleware's first assertion); the server watches each with that lease, and counts
it as the agent's request topic's. A node still listed in the ROS graph whose publisher is
matched but no longer alive is *out of reach*: a network cut, or a frozen process.
That is told within the lease, long before DDS drops the participant (its own lease: 2 s on one
machine, 10 s across hosts in scripts/two_hosts.sh), and it ends as soon as the link is back.
A publisher dropped without a lapse counted first (a clean stop, or a killed process whose
lapse and drop the server read as one change) has *ended*: its info node says gone at once; its
claims wait for the server's agent_grace, as those of a node that left the ROS graph do.

The server ends the claims of an agent out of reach (reason ``unreachable``; the agent takes
them again when it hears of it) and lists such agents in its heartbeat, so agents on the other
side of a cut can tell that what the patient said may still be on its way (PELEA).
"""

from __future__ import annotations

from dataclasses import dataclass, field

PRESENCE_LEASE = 1.0  # seconds: offered by agents' presence publishers, requested by the server


@dataclass
class Presence:
    """Liveliness counts per request topic, and since when each agent has been out of reach."""

    # topic -> (its agent, publishers alive, publishers matched but not alive)
    _counts: dict[str, tuple[str, int, int]] = field(default_factory=dict)
    _away_since: dict[str, float] = field(default_factory=dict)  # agent -> when first seen away
    _ended: list[str] = field(default_factory=list)  # agents one of whose processes ended

    def observe(self, topic: str, agent: str, alive: int, not_alive: int) -> None:
        """DDS reported the counts of ``topic``'s publishers (``agent``: its owner's name)."""
        before = self._counts.get(topic)
        if before is not None:
            lapsed = not_alive > before[2]
            if (lapsed and alive) or (alive < before[1] and not lapsed):
                # One of its publishers lapsed while another is alive (a process killed and
                # respawned at once is never "away"), or one went unmatched without a lapse
                # counted: its process ended. A loaded server reads its liveliness events
                # late and DDS reports the counts as they are then: the lapse and the drop of
                # a killed process's participant came as one (1 alive -> 0, none lapsed), and
                # a successor up within the ROS graph's grace was the agent all along.
                self._ended.append(agent)
        self._counts[topic] = (agent, alive, not_alive)

    def take_ended(self) -> list[str]:
        """Agents one of whose processes ended (or lapsed while another of that name is
        alive), since the last call: their info nodes say gone; one alive writes its state
        again (ros/agent.py describes itself until the graph shows it as it is)."""
        ended, self._ended = sorted(set(self._ended)), []
        return ended

    def liveliness(self, topic: str) -> tuple[int, int] | None:
        """(alive, matched but not alive) publishers of ``topic`` as DDS last counted them."""
        counts = self._counts.get(topic)
        return None if counts is None else counts[1:]

    def update(self, now: float) -> tuple[list[str], list[tuple[str, float]]]:
        """(agents newly out of reach, [(agent back in reach, seconds it was away)])."""
        away = {a for a, alive, not_alive in self._counts.values() if not_alive and not alive}
        lost = sorted(away - set(self._away_since))
        back = sorted((a, now - t) for a, t in self._away_since.items() if a not in away)
        for agent in lost:
            self._away_since[agent] = now
        for agent, _ in back:
            del self._away_since[agent]
        return lost, back

    @property
    def away(self) -> list[str]:
        """Agents out of reach at the last ``update``."""
        return sorted(self._away_since)

    @property
    def alive(self) -> set[str]:
        """Agents with a presence publisher alive now: their processes run, whatever the ROS
        graph lists (under heavy load it left live nodes out for minutes, and the server marked
        their info nodes gone every few seconds: protocol/absence.py)."""
        return {agent for agent, alive, _ in self._counts.values() if alive}
