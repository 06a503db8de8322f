"""A subscribing agent for the throughput benchmark: a DsrAgent replica that counts the deltas it
actually applies until its replica reaches seq N (or, with --raw, a plain String subscription
that counts the messages it receives, up to N), prints the count, when the first and the last
arrived and how often the replica resynchronised from a snapshot (deltas a snapshot covered are
not counted: they were never applied one by one), then exits. Usage: counter.py N [--raw TOPIC]"""

import json
import sys
import time

from std_msgs.msg import String

from dsr_graph.ros.agent import DsrAgent
from dsr_graph.ros.dsr_node import DsrNode
from dsr_graph.ros.qos import qos_stream
from dsr_graph.ros.session import RosSession


def main() -> int:
    n = int(sys.argv[1])
    raw = sys.argv[3] if len(sys.argv) > 3 and sys.argv[2] == "--raw" else None
    seen = {"count": 0, "first": None, "last": None, "seq": 0, "resyncs": 0}

    def count(k: int) -> None:
        if k <= 0:
            return
        now = time.time()
        seen["first"] = seen["first"] or now
        seen["count"] += k
        seen["last"] = now

    def applied(deltas, resynced: bool) -> None:
        seen["seq"] = agent.replica.seq
        count(len(deltas))

    # spun as the robot's agents are, on both sides (DsrNode.EXECUTOR: rclpy's EventsExecutor)
    with RosSession(executor=DsrNode.EXECUTOR) as ros:
        if raw:
            ros.node.create_subscription(String, raw, lambda m: count(1), qos_stream())
        else:
            agent = DsrAgent()
            agent.setup(ros.node, timeout_sec=30)
            ros.spin_until(lambda: agent.ready, 30, "the server")
            seen["seq"] = agent.replica.seq
            agent.add_listener(applied)
            seen["start_seq"] = seen["seq"]
        print("ready", flush=True)
        # Stop at n (messages, or the replica's seq), or when nothing more came for 3 s (a
        # subscriber that fell behind may have lost messages: the report says how many arrived).
        deadline = time.time() + 120
        while (
            seen["count"] < n
            and (raw or seen["seq"] - seen["start_seq"] < n)
            and time.time() < deadline
        ):
            if seen["last"] is not None and time.time() - seen["last"] > 3:
                break
            ros.executor.spin_once(timeout_sec=0.05)
    if not raw:  # the first snapshot is the late join, not a resynchronisation
        seen["resyncs"] = agent.resyncs - 1
    print(json.dumps(seen), flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
