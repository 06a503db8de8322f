"""Which agents have left the ROS graph for good (pure; the server feeds it the node names it
lists at each heartbeat).

Two things end when an agent's process does, each after its own wait:
- its claims, after ``agent_grace`` (a restarted agent takes them again; ending them early would
  hand a patient's item to another agent mid-answer);
- its info node's state, marked gone after ``info_grace``, shorter: a wrong mark costs nothing,
  the agent writes its state again when it is heard (model/agent_info.py). Not while the server
  is still ``warm``-ing up: its first seconds' ROS graph is still filling.
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass, field


@dataclass
class Absences:
    """Since when each claim holder or described agent has been missing from the ROS graph."""

    _since: dict[str, float] = field(default_factory=dict)

    def update(
        self,
        holders: set[str],
        described: set[str],
        live: Iterable[str],
        now: float,
        *,
        grace: float,
        info_grace: float,
        warm: bool,
    ) -> tuple[list[str], list[str]]:
        """(holders missing for ``grace``: their claims end, described agents missing for
        ``info_grace``: their info nodes say gone). Each agent is told once: its absence starts
        again if it stays away."""
        live = set(live)
        watched = holders | described
        for agent in list(self._since):
            if agent not in watched or agent in live:
                del self._since[agent]
        claims_gone, info_gone = [], []
        for agent in sorted(watched - live):
            missing = now - self._since.setdefault(agent, now)
            info_due = agent in described and warm and missing >= info_grace
            claims_due = agent in holders and missing >= grace
            if info_due:
                info_gone.append(agent)
            if claims_due:
                claims_gone.append(agent)
            if claims_due or (info_due and agent not in holders):
                del self._since[agent]
        return claims_gone, info_gone
