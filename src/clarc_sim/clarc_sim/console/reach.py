"""Which of the robot's nodes the ROS graph can reach, as it changes (pure): the monitor's way to
show a node dying or a network cut between hosts. A node counts once it has been seen; it is out
of reach when the ROS graph stops listing it (DDS drops a participant not heard for its lease
duration), and back when it is listed again."""

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
