"""A subscribing agent for the throughput benchmark: a DsrAgent replica that waits until its
replica reaches seq N (or, with --raw, a plain String subscription that waits for N messages),
prints when the first and the last arrived, then exits. Usage: counter.py N [--raw TOPIC]"""

import json
import sys
import time

from std_msgs.msg import String

from dsr_graph.ros.agent import DsrAgent
from dsr_graph.ros.qos import qos_stream
from dsr_graph.ros.session import RosSession


def main() -> int:
    n = int(sys.argv[1])
    raw = sys.argv[3] if len(sys.argv) > 3 and sys.argv[2] == "--raw" else None
    seen = {"count": 0, "first": None, "last": None}

    def count(k: int) -> None:
        if k <= 0:  # the first snapshot, or a resync that brought nothing new
            return
        now = time.time()
        seen["first"] = seen["first"] or now
        seen["count"] += k
        seen["last"] = now

    with RosSession() as ros:
        if raw:
            ros.node.create_subscription(String, raw, lambda m: count(1), qos_stream())
        else:
            agent = DsrAgent()
            agent.setup(ros.node, timeout_sec=30)
            # by seq, not by count: a replica that resynchronised from a snapshot skipped deltas
            agent.add_listener(lambda deltas, resynced: count(agent.replica.seq - seen["count"]))
            ros.spin_until(lambda: agent.ready, 30, "the server")
        print("ready", flush=True)
        # Stop at n, or when nothing more came for 3 s (a raw subscriber that fell behind may have
        # lost messages: the report then says how many arrived).
        deadline = time.time() + 120
        while seen["count"] < n and time.time() < deadline:
            if seen["last"] is not None and time.time() - seen["last"] > 3:
                break
            ros.executor.spin_once(timeout_sec=0.05)
    if not raw:
        seen["resyncs"] = agent.resyncs
    print(json.dumps(seen), flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
