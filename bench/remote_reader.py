"""The latency rig's timed reader, in a process of its own as a reading agent is on the robot:
a DSR replica and a raw subscription to the relay's output topic. Each arrival's
``time.perf_counter()`` (CLOCK_MONOTONIC: one clock for every process of the machine) goes to
stdout as a line, ``d <delta id> <seconds> <its callback's start>`` or ``r <seconds>``,
written after the times are taken. Says ``ready`` once the replica is synced and the relay is
matched.
Usage: remote_reader.py DOMAIN NAME RAW_TOPIC"""

import sys
import time

from harness import session_with_agent
from std_msgs.msg import String

from dsr_graph.ros.qos import qos_stream


def main() -> int:
    domain, name, raw_topic = int(sys.argv[1]), sys.argv[2], sys.argv[3]
    ros, agent = session_with_agent(domain, name)
    out = sys.stdout

    plain, started = agent._delta_sub.callback, [0.0]

    def timed(msg) -> None:  # when the callback took the message, for latency.stages
        started[0] = time.perf_counter()
        plain(msg)

    agent._delta_sub.callback = timed

    def deltas(batch, resynced) -> None:
        now = time.perf_counter()
        # the server's own deltas (an agent gone, ...) have an empty id: not a timed change
        out.write("".join(f"d {d['id']} {now!r} {started[0]!r}\n" for d in batch if d.get("id")))
        out.flush()

    def raw(msg) -> None:
        now = time.perf_counter()
        out.write(f"r {now!r}\n")
        out.flush()

    agent.add_listener(deltas)
    ros.node.create_subscription(String, raw_topic, raw, qos_stream())
    try:
        ros.spin_until(lambda: ros.node.count_publishers(raw_topic) > 0, 30, "the relay")
        out.write("ready\n")
        out.flush()
        while ros.context.ok():  # until the rig's SIGINT
            ros.executor.spin_once(timeout_sec=0.5)
    except (KeyboardInterrupt, BrokenPipeError):
        pass
    finally:
        ros.close()
    return 0


if __name__ == "__main__":
    sys.exit(main())
