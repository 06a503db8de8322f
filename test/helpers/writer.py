"""A writer agent for tests: sends N transactions as fast as it can and exits 0 once every one
was answered (accepted or not), printing how many were accepted. Usage: writer.py PREFIX N"""

import sys

from dsr_graph.ros.agent import DsrAgent
from dsr_graph.ros.session import RosSession


def main() -> int:
    prefix, n = sys.argv[1], int(sys.argv[2])
    with RosSession(name=f"writer_{prefix}") as ros:
        agent = DsrAgent(describe=False)  # a load generator, not one of the agents
        agent.setup(ros.node, timeout_sec=15)
        ros.spin_until(lambda: agent.ready, 15, "the server")
        results = []
        for i in range(n):
            agent.send(
                {"ops": [{"op": "insert_node", "name": f"{prefix}{i}", "type": "transform"}]},
                results.append,
            )
        ros.spin_until(lambda: len(results) == n, 30, "all verdicts")
        print(sum(r.accepted for r in results), flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
