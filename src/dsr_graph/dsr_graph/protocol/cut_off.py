"""Telling an agent that its own middleware has cut it off from the DSR server (pure; the ROS
link asks the middleware and runs the probe).

Seen here (Fast DDS 2.14 as the suite sets it up: shared memory and UDP, a 2 s participant
lease): a server stalled for longer than the lease (SIGSTOP for 4 s, then SIGCONT) is dropped by
its agents' participants and, once it runs again, some of them never match it again: the
agent's request publisher stays without the server's reader (its requests reach no one) or its
delta subscription without the server's writer, for as long as it was watched (40 s; 2 runs in
3 of a /tmp script whose agent lived in the script's process, 1 in 10 of
test/system/test_server_stall.py), while a participant made afresh sees both at once. Nothing in
the agent can rebuild its participant, so a node that finds itself so ends, to be restarted by
its launch, as one whose participant Fast DDS deadlocked does (ros/dds_deadlock.py). (The
stall's other outcome, a server that no longer knows the agent's node name, is told by its
refusals: ros/agent.py.)

An agent whose request or delta topic has been unmatched for ``CUT_OFF_AFTER`` seconds asks a
fresh participant (the probe). If the probe sees the server's end of both while the agent's own
ends are still unmatched, the agent is cut off. A server that is simply down (killed,
restarting) is seen by no probe: nothing happens, and the next probe waits twice as long as the
one before (``PROBE_EVERY`` first, ``PROBE_AT_MOST`` at most), so that a long outage costs every
agent a probe a minute or so, not one every few seconds (a probe is a process start, 0.33 CPU s).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

CUT_OFF_AFTER = 5.0  # seconds unmatched before a probe (a server's restart takes 1 to 3 s)
PROBE_EVERY = 10.0  # seconds from a probe that saw no server to the next, at first
PROBE_AT_MOST = 80.0  # ... doubling each time up to this
LOOK_EVERY = 1.0  # seconds between two looks at the agent's own matches (two rcl queries)


@dataclass
class CutOffWatch:
    unmatched_since: float | None = None
    probing: bool = False
    last_probe: float = -math.inf
    last_look: float = -math.inf
    misses: int = 0  # probes in a row that saw no server

    @property
    def every(self) -> float:
        """Seconds from the last probe to the next while unmatched."""
        if not self.misses:
            return PROBE_EVERY
        return min(PROBE_EVERY * 2 ** (self.misses - 1), PROBE_AT_MOST)

    def due_look(self, now: float) -> bool:
        """Whether the agent's matches are to be looked at now."""
        if now - self.last_look < LOOK_EVERY:
            return False
        self.last_look = now
        return True

    def look(self, matched: bool, now: float) -> bool:
        """Take what the agent's own endpoints show (``matched``: both its request and its
        delta topic have the server's end); True: start a probe now."""
        if matched:
            self.unmatched_since, self.misses = None, 0
            return False
        if self.unmatched_since is None:
            self.unmatched_since = now
        if self.probing or now - self.unmatched_since < CUT_OFF_AFTER:
            return False
        if now - self.last_probe < self.every:
            return False
        self.probing, self.last_probe = True, now
        return True

    def probed(self, server_seen: bool, matched_now: bool) -> bool:
        """The probe's answer (``server_seen``: a fresh participant sees the server's end of
        both topics); True: the agent is cut off."""
        self.probing = False
        if matched_now:
            self.unmatched_since, self.misses = None, 0
        elif not server_seen:  # the server is down: look again later and later
            self.misses += 1
        return server_seen and not matched_now
