"""Whether a participant made afresh sees the DSR server's end of an agent's topics
(protocol/cut_off.py): run by the agent as a process of its own, so that its own participant and
executor are never held.

    python -m dsr_graph.ros.server_probe DOMAIN_ID DELTAS_TOPIC REQUEST_TOPIC

prints ``seen`` once the ROS graph shows a publisher on DELTAS_TOPIC and a subscriber on
REQUEST_TOPIC (both fully qualified), ``unseen`` if not within ``WAIT`` seconds, and ends at once
(no DDS teardown to wait on: the participant goes with the process)."""

from __future__ import annotations

import os
import subprocess
import sys
import time

import rclpy

from dsr_graph.ros.exit_timer import exit_now

WAIT = 3.0  # seconds the probe's participant takes to discover the domain, at most


def main(argv: list[str]) -> int:
    domain, deltas, requests = int(argv[0]), argv[1], argv[2]
    rclpy.init(domain_id=domain)
    # nothing of its own in the graph but its name: no rosout, no parameter services
    node = rclpy.create_node(
        f"dsr_probe_{os.getpid()}", enable_rosout=False, start_parameter_services=False
    )
    deadline = time.monotonic() + WAIT
    seen = False
    while not seen and time.monotonic() < deadline:
        time.sleep(0.1)  # the graph is filled by the middleware's own threads
        seen = node.count_publishers(deltas) > 0 and node.count_subscribers(requests) > 0
    print("seen" if seen else "unseen", flush=True)
    exit_now(0)
    return 0


class ServerProbe:
    """A probe running as a process of its own, asked without waiting."""

    def __init__(self, domain: int, deltas: str, requests: str):
        self.process = subprocess.Popen(
            [sys.executable, "-m", "dsr_graph.ros.server_probe", str(domain), deltas, requests],
            stdin=subprocess.DEVNULL,
            stdout=subprocess.PIPE,
            stderr=subprocess.DEVNULL,
            text=True,
        )

    def answer(self) -> bool | None:
        """True: the probe saw the server's end of both topics; None: not told yet."""
        if self.process.poll() is None:
            return None
        out = self.process.stdout.read() if self.process.stdout else ""
        self.process.stdout.close()
        return out.strip() == "seen"


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
