"""What the monitor can tell about reach, as it changes (pure): which of the robot's nodes the ROS
graph lists (a node counts once it has been seen; it is out of reach when the graph stops listing
it, as DDS drops a participant not heard for its lease, and back when listed again), whether
the DSR server's heartbeat has gone silent (it died, or the network to it is cut), and where
each agent stands when a test did not finish."""

from __future__ import annotations

from collections.abc import Iterable


class Reach:
    def __init__(self, watched: Iterable[str]):
        self.watched = set(watched)  # fully qualified node names
        self.seen: set[str] = set()
        self.lost: set[str] = set()

    def update(self, listed: Iterable[str]) -> list[str]:
        """The lines to show for a new listing of the ROS graph's nodes (fully qualified)."""
        here = self.watched & set(listed)
        gone = (self.seen - here) - self.lost
        back = self.lost & here
        self.seen |= here
        self.lost = (self.lost - back) | gone
        lines = []
        if gone:
            lines.append(f"out of reach: {', '.join(sorted(gone))}")
        if back:
            lines.append(f"back in reach: {', '.join(sorted(back))}")
        return lines


class HeartbeatSilence:
    """The server's heartbeat going silent for more than ``threshold`` seconds, and coming back."""

    def __init__(self, threshold: float):
        self.threshold = threshold
        self.since: float | None = None  # the last beat before the silence

    def update(self, heard: float | None, now: float) -> str | None:
        """A line to show, given when the last beat was heard (None: never) and the time now."""
        if heard is None:
            return None
        silent = now - heard
        if silent > self.threshold and self.since is None:
            self.since = heard
            return f"the DSR server is out of reach (no heartbeat for {silent:.1f} s)"
        if silent <= self.threshold and self.since is not None:
            gap, self.since = heard - self.since, None
            return f"the DSR server is back in reach after {gap:.1f} s"
        return None


def where_agents_stand(agents: list[dict], listed: Iterable[str]) -> str:
    """One line for a test that did not finish: each agent as its info node in the DSR says
    (``agent_info.listing``: state and process), and the ROS nodes listed that have none (a
    process up whose agent never joined the DSR)."""
    described = [
        f"{a['name']} {a.get('state') or '?'}" + (f" (pid {a['pid']})" if a.get("pid") else "")
        for a in agents
    ]
    others = sorted(set(listed) - {a["name"] for a in agents})
    return (
        f"agents as the DSR shows them: {', '.join(described) or 'none'}; "
        f"ROS nodes with no agent info: {', '.join(others) or 'none'}"
    )
