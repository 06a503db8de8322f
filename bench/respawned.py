"""An agent for the restart benchmark: joins the DSR under the node name given, writes one change
and prints, as one JSON line, how long after its start it was in sync (ready) and had its change
accepted; then stays until killed. Usage: respawned.py NODE_NAME"""

import json
import sys
import time

start = time.time()

from dsr_graph.ros.agent import DsrAgent  # noqa: E402 (the start is timed before the imports)
from dsr_graph.ros.session import RosSession  # noqa: E402


def main() -> int:
    with RosSession(name=sys.argv[1]) as ros:
        agent = DsrAgent()
        agent.setup(ros.node, timeout_sec=30)
        ros.spin_until(lambda: agent.ready, 30, "the server")
        ready = time.time()
        done: list = []
        change = {"ops": [{"op": "set_node_attrs", "node": "room", "attrs": {"color": "White"}}]}
        agent.send(change, done.append)
        ros.spin_until(lambda: done, 30, "the verdict")
        print(
            json.dumps(
                {
                    "ready_s": ready - start,
                    "accepted_s": time.time() - start,
                    "accepted": done[0].accepted,
                }
            ),
            flush=True,
        )
        ros.follow(lambda: False)
    return 0


if __name__ == "__main__":
    sys.exit(main())
