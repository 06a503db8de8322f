"""A subscribing agent for the throughput benchmark, counting in bursts: a DsrAgent replica that
counts the deltas it applies one by one (or, with --raw TOPIC, a plain String subscription that
counts the messages it receives). It prints "ready", then for each line "N" read on stdin prints
"armed", counts until N more arrived (the replica's seq N further, or N messages) or nothing came
for 3 s, from the arming on (a subscriber that fell behind may have lost some: the line says how
many came), and prints one JSON line: the count, when the first and the last arrived, and the
resynchronisations from a snapshot during the burst (deltas a snapshot covered were never applied
one by one).
Exits at the end of stdin. Usage: counter.py [--raw TOPIC]"""

import json
import selectors
import sys
import time

from std_msgs.msg import String

from dsr_graph.ros.agent import DsrAgent
from dsr_graph.ros.qos import qos_stream
from dsr_graph.ros.session import RosSession

SILENCE = 3.0  # seconds without anything new that end a burst
LONGEST = 120.0  # seconds a burst may last in all


def main() -> int:
    raw = sys.argv[2] if len(sys.argv) > 2 and sys.argv[1] == "--raw" else None
    seen = {"count": 0, "first": None, "last": None}

    def count(k: int) -> None:
        if k <= 0:
            return
        now = time.time()
        seen["first"] = seen["first"] or now
        seen["count"] += k
        seen["last"] = now

    with RosSession() as ros:
        agent = None
        if raw:
            ros.node.create_subscription(String, raw, lambda m: count(1), qos_stream())
        else:
            agent = DsrAgent()
            agent.setup(ros.node, timeout_sec=30)
            ros.spin_until(lambda: agent.ready, 30, "the server")
            agent.add_listener(lambda deltas, resynced: count(len(deltas)))
        print("ready", flush=True)
        stdin = selectors.DefaultSelector()
        stdin.register(sys.stdin, selectors.EVENT_READ)
        while True:
            while not stdin.select(timeout=0.05):  # the replica keeps up between bursts
                ros.executor.spin_once(timeout_sec=0)
            line = sys.stdin.readline()
            if not line:
                return 0
            n = int(line)
            seen.update(count=0, first=None, last=None)
            start_seq = agent.replica.seq if agent else 0
            resyncs = agent.resyncs if agent else 0
            print("armed", flush=True)
            armed = time.time()
            while (
                seen["count"] < n
                and (raw or agent.replica.seq - start_seq < n)
                and time.time() - armed < LONGEST
                and time.time() - (seen["last"] or armed) < SILENCE
            ):
                ros.executor.spin_once(timeout_sec=0.05)
            resynced = agent.resyncs - resyncs if agent else 0
            print(json.dumps(seen | {"resyncs": resynced}), flush=True)


if __name__ == "__main__":
    sys.exit(main())
