"""A replica that asks for the bytes of binary values (``DsrAgent(blobs=True)``, as the viewer):
for SECONDS after it is ready, counts the camera images that reach its graph whole (``cam_rgb``
an array) and those that did not (a ``BlobRef``: the bytes did not come in time), then prints
them as JSON. Usage: image_counter.py SECONDS"""

import json
import sys
import time

import numpy as np

from dsr_graph.ros.agent import DsrAgent
from dsr_graph.ros.session import RosSession


def main() -> int:
    seconds = float(sys.argv[1])
    seen = {"whole": 0, "unfetched": 0, "resyncs": 0}
    with RosSession(name="image_counter") as ros:
        agent = DsrAgent(blobs=True)
        agent.setup(ros.node, timeout_sec=30)
        ros.spin_until(lambda: agent.ready, 30, "the server")

        def applied(deltas, resynced: bool) -> None:
            for delta in deltas:
                for op in delta.get("ops", []):
                    value = (op.get("attrs") or {}).get("cam_rgb")
                    if value is not None:
                        seen["whole" if isinstance(value, np.ndarray) else "unfetched"] += 1

        agent.add_listener(applied)
        print("ready", flush=True)
        start = time.time()
        while time.time() - start < seconds:
            ros.executor.spin_once(timeout_sec=0.05)
        seen["seconds"] = time.time() - start
        seen["resyncs"] = agent.resyncs - 1
    print(json.dumps(seen), flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
