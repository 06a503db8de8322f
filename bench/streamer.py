"""A sensor stream in a process of its own, as the robot's camera and Person nodes are: the
camera's images (node ``camera``) or a patient's skeleton (node ``person``) at 30 Hz into the
DSR, switched on and off by the benchmark. In the benchmark's own process, each frame was made
and sent between the measured change's send and its arrival, so the stream's work was counted in
that change's latency: a cost of the benchmark, not of the DSR.

Usage: streamer.py camera|skeleton. Says "ready" once its replica is synced; then reads lines:
"on" (the stream starts, counts from zero), "off" (it stops and prints its counts as JSON:
offered, written and seconds; the skeleton's also txs, volatile and delta_bytes); it ends at the
end of its input."""

from __future__ import annotations

import json
import os
import queue
import sys
import threading
import time

from harness import session_with_agent
from streams import CameraStream, SkeletonStream

NODES = {"camera": "camera", "skeleton": "person"}


def counts(stream, seconds: float) -> dict[str, float]:
    if isinstance(stream, CameraStream):
        return {"offered": stream.offered, "written": stream.written, "seconds": seconds}
    return {
        "offered": stream.frames,
        "written": stream.written,
        "txs": stream.txs,
        "volatile": stream.volatile,
        "delta_bytes": stream.delta_bytes(),
        "seconds": seconds,
    }


def main() -> int:
    kind = sys.argv[1]
    ros, agent = session_with_agent(int(os.environ["ROS_DOMAIN_ID"]), NODES[kind])
    try:
        stream = CameraStream(agent) if kind == "camera" else SkeletonStream(agent, ros)
        commands: queue.Queue[str] = queue.Queue()

        def read() -> None:  # stdin on a thread of its own: the stream never waits for it
            for line in sys.stdin:
                commands.put(line.strip())
            commands.put("")  # the end of the input

        threading.Thread(target=read, daemon=True).start()
        print("ready", flush=True)
        on, since = False, time.perf_counter()
        while ros.context.ok():  # a SIGINT (Procs.stop_all) shuts it down
            try:
                command = commands.get_nowait()
            except queue.Empty:
                command = None
            if command == "on":
                stream.restart()
                on, since = True, time.perf_counter()
            elif command == "off":
                on = False
                print(json.dumps(counts(stream, time.perf_counter() - since)), flush=True)
            elif command == "":
                return 0
            if on:
                stream.step()
            ros.executor.spin_once(timeout_sec=0.001 if on else 0.01)
        return 0
    finally:
        ros.close()


if __name__ == "__main__":
    try:
        sys.exit(main())
    except KeyboardInterrupt:  # Procs.stop_all: the session closed on the way out
        sys.exit(0)
