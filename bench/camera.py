"""The camera and the skeleton streaming into the DSR: the server's CPU, images offered, written and
delivered whole, a Speech change's latency against the quiet figure."""

from __future__ import annotations

import json
import sys
import time
from pathlib import Path
from typing import Any

from harness import HERE, ROOT, Procs, _wait_ready, agent_session, server_cpu, timed_reader
from streams import Streamer, hop_costs, quiet_and_streaming, streaming


def bench_camera(
    work: Path, domain: int, seconds: float, rounds: int, per_round: int
) -> dict[str, Any]:
    """The camera (640x480 colour and depth, 30 Hz) and the skeleton (30 Hz) streaming into the
    DSR together, each from a process of its own as in the robot: the server's CPU, images
    offered, written and delivered whole to a replica that asks for the bytes (another process),
    and a Speech-sized change's latency (from Speech's node, read by another), each against the
    same without the streams (the latency in interleaved rounds); and what one hop costs a frame
    as base64 JSON or as blobs."""
    out: dict[str, Any] = {"hop": hop_costs()}
    with Procs(work, domain) as procs:
        server = procs.server(
            work / f"camera_state_{domain}", str(ROOT / "worlds" / "clarc_room.json")
        )
        streams = [Streamer(procs, "camera"), Streamer(procs, "skeleton")]
        with agent_session(domain, "speech") as (ros, speech):
            _, _, arrived = timed_reader(ros)
            out["server_cpu_idle"] = server_cpu(server, ros, seconds, lambda: None)
            counter = procs.start(
                "image_counter", [sys.executable, str(HERE / "image_counter.py"), str(seconds)]
            )
            _wait_ready(counter)
            t0 = time.perf_counter()
            with streaming(streams) as counts:
                out["server_cpu_streaming"] = server_cpu(server, ros, seconds, lambda: None)
                elapsed = time.perf_counter() - t0
            images, skeleton = counts
            counted = json.loads(counter.stdout.readline() or counter.communicate(timeout=30)[0])
            out["frames_offered_per_s"] = images["offered"] / elapsed
            out["frames_written_per_s"] = images["written"] / elapsed
            out["frames_delivered_per_s"] = counted["whole"] / counted["seconds"]
            out["frames_unfetched"] = counted["unfetched"]
            out["reader_resyncs"] = counted["resyncs"]
            out["skeleton_frames_written_per_s"] = skeleton["written"] / elapsed
            out |= quiet_and_streaming(ros, speech, arrived, rounds, per_round, streams)
    return out
