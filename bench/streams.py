"""The sensor streams the robot writes: a patient's skeleton at 30 Hz as Person writes it, the
camera's colour and depth images at 30 Hz (each run in a process of its own by streamer.py,
switched on and off through ``Streamer``), and what one hop costs a frame."""

from __future__ import annotations

import contextlib
import json
import random
import select
import sys
import time
from pathlib import Path
from subprocess import PIPE
from typing import Any

import numpy as np
from harness import (
    HERE,
    ROOT,
    Procs,
    _wait_ready,
    agent_session,
    latency_samples,
    server_cpu,
    speech_change,
    timed_reader,
)
from rounds import interleave, pooled, ratio

from dsr_graph.ros.agent import DsrAgent


class SkeletonStream:
    """Person at 30 Hz, as it writes (frames taken while a transaction is in flight go together in
    the next, ``frames_tx``): ``step()`` offers a frame when one is due and sends what waits."""

    def __init__(self, person: DsrAgent, ros):
        from clarc_agents.gug.skeleton import frames_tx, parse_skeleton
        from clarc_sim.devices.skeleton_frames import KinectModel, TrialPlace, skeleton
        from clarc_sim.patient.gait_motion import Motion

        done: list = []
        person.send(
            {
                "ops": [
                    {"op": "insert_node", "name": "person", "type": "person", "attrs": {}},
                    {
                        "op": "insert_edge",
                        "from": "kinect",
                        "to": "person",
                        "type": "RT",
                        "rt": {"translation": [4.3, 0, -0.7], "rotation_euler_xyz": [0, 0, 0]},
                    },
                ]
            },
            done.append,
        )
        ros.spin_until(lambda: done, 10, "the person")
        self.motion = Motion(reaction=1.0, rise=2.0, walk_out=4.0, turn=2.0, walk_back=4.0, sit=3.0)
        place, sensor = (
            TrialPlace(4500.0, 0.0, -1200.0, 3.14159),
            KinectModel(random.Random(3), 10.0),
        )
        self.frame = lambda t: parse_skeleton(sensor.see(skeleton(self.motion, t, place), t)[0])
        self.frames_tx, self.person = frames_tx, person
        self.restart()

    def restart(self) -> None:
        self.next, self.frames, self.written, self.txs, self.volatile = (
            time.perf_counter(),
            0,
            0,
            0,
            0,
        )
        self.waiting: list = []
        self.in_flight = False

    def step(self) -> None:
        now = time.perf_counter()
        if now >= self.next:
            # a frame every 1/30 s from now on; frames not offered while we did not run are
            # lost, as a Kinect's are
            self.next = max(self.next, now - 1.0 / 30.0) + 1.0 / 30.0
            self.frames += 1
            t = (self.frames / 30.0) % (self.motion.total + 3.0) - 1.0
            self.waiting.append((self.frame(t), time.time()))
        if self.in_flight or not self.waiting:
            return
        batch, self.waiting = self.waiting, []
        self.in_flight = True

        def written(r) -> None:
            self.in_flight = False
            self.txs += 1
            self.written += len(batch) if r.accepted else 0
            self.volatile += bool(r.accepted and "volatile" in r.delta)

        self.person.send(self.frames_tx(self.person.graph, batch), written)

    def delta_bytes(self) -> int:
        return len(json.dumps(self.frames_tx(self.person.graph, [(self.frame(0.0), time.time())])))


OFF_WITHIN = 30.0  # seconds a stream process may take to stop and give its counts


class Streamer:
    """A sensor stream (``camera`` or ``skeleton``) in a process of its own (streamer.py), as the
    robot's camera and Person are, switched on and off; ``off()`` gives its counts."""

    def __init__(self, procs: Procs, kind: str):
        script = str(HERE / "streamer.py")
        self.process = procs.start(f"streamer_{kind}", [sys.executable, script, kind], PIPE)
        _wait_ready(self.process)

    def _say(self, line: str) -> None:
        self.process.stdin.write(line + "\n")
        self.process.stdin.flush()

    def on(self) -> None:
        self._say("on")

    def off(self) -> dict[str, Any]:
        self._say("off")
        # the process's own waits are bounded; this one too, should it hang all the same
        answered, _, _ = select.select([self.process.stdout], [], [], OFF_WITHIN)
        if not answered:
            raise RuntimeError(f"a stream process did not answer 'off' within {OFF_WITHIN:g} s")
        line = self.process.stdout.readline()
        if not line:
            raise RuntimeError(f"a stream process ended (exit {self.process.poll()})")
        return json.loads(line)


@contextlib.contextmanager
def streaming(streamers: list[Streamer]):
    """The streams on for the block; their counts, once it ends, in the list it gives."""
    for s in streamers:
        s.on()
    counts: list[dict[str, Any]] = []
    try:
        yield counts
    finally:
        counts += [s.off() for s in streamers]


def quiet_and_streaming(
    ros, speech, arrived, rounds: int, per_round: int, streamers: list[Streamer]
) -> dict[str, Any]:
    """A Speech-sized change's latency without and with the streams, in interleaved rounds
    (rounds.py): the pooled percentiles of each side, and the per-round ratios of streaming
    over quiet."""

    def quiet(r: int) -> list[float]:
        ros.spin_for(0.3)  # what the stream left on its way goes first
        return latency_samples(ros, speech, arrived, per_round, speech_change)

    def streamed(r: int) -> list[float]:
        with streaming(streamers):
            ros.spin_for(0.3)  # the streams under way
            return latency_samples(ros, speech, arrived, per_round, speech_change)

    runs = interleave({"quiet": quiet, "streaming": streamed}, rounds)
    return {
        "latency_quiet": pooled(runs["quiet"]),
        "latency_streaming": pooled(runs["streaming"]),
        "ratios": {
            f"streaming_vs_quiet_{stat[:3]}": ratio(runs["streaming"], runs["quiet"], stat)
            for stat in ("p50_ms", "p99_ms")
        },
    }


def gug_stream(
    work: Path, domain: int, seconds: float, rounds: int, per_round: int
) -> dict[str, Any]:
    """A patient's skeleton at 30 Hz written as Person writes it (a process of its own): the
    server's CPU, frames written of those offered, a Speech-sized change's latency (interleaved
    rounds) and the journal's growth, each against the same without the stream."""
    state = work / f"gug_state_{domain}"
    out: dict[str, Any] = {}
    with Procs(work, domain) as procs:
        server = procs.server(state, str(ROOT / "worlds" / "clarc_room.json"))
        skeleton = Streamer(procs, "skeleton")
        with agent_session(domain, "speech") as (ros, speech):
            _, _, arrived = timed_reader(ros)
            out["server_cpu_idle"] = server_cpu(server, ros, seconds, lambda: None)
            journal = state / "journal.jsonl"
            size0, t0 = journal.stat().st_size if journal.exists() else 0, time.perf_counter()
            largest, sizes = [size0], {"last": size0, "grown": 0}

            def journal_growth() -> None:
                if journal.exists():
                    size = journal.stat().st_size
                    largest[0] = max(largest[0], size)
                    # appended since the last look (after a compaction: the new journal's size)
                    sizes["grown"] += size - sizes["last"] if size >= sizes["last"] else size
                    sizes["last"] = size

            with streaming([skeleton]) as counts:
                out["server_cpu_streaming"] = server_cpu(server, ros, seconds, journal_growth)
                elapsed = time.perf_counter() - t0
            (stream,) = counts
            out["frames_written_per_s"] = stream["written"] / elapsed
            out["frames_offered_per_s"] = stream["offered"] / elapsed
            out["frames_per_tx"] = stream["written"] / max(stream["txs"], 1)
            out["delta_bytes"] = stream["delta_bytes"]
            out["volatile_share"] = stream["volatile"] / max(stream["txs"], 1)
            out["journal_bytes_per_min"] = sizes["grown"] / elapsed * 60
            out["journal_largest_bytes"] = largest[0]
            out["compact_every"] = 1000
            out |= quiet_and_streaming(ros, speech, arrived, rounds, per_round, [skeleton])
    return out


# ---------------------------------------------------------------------------- 7. camera
class CameraStream:
    """The camera agent at 30 Hz: a 640x480 colour image and a depth image (float32 metres) of
    the room, at most two transactions on their way, each with the newest images."""

    def __init__(self, camera: DsrAgent):
        from clarc_sim.devices.camera_images import CameraModel

        self.model, self.camera = CameraModel(640, 480), camera
        self.restart()

    def restart(self) -> None:
        self.next, self.offered, self.written, self.in_flight = time.perf_counter(), 0, 0, 0
        self.pending: dict[str, Any] | None = None

    def step(self) -> None:
        now = time.perf_counter()
        if now >= self.next:
            self.next = max(self.next, now - 1.0 / 30.0) + 1.0 / 30.0
            rgb, depth = self.model.frame(self.offered, (1500.0, 0.0, 300.0))
            self.offered += 1
            attrs = {"cam_rgb": rgb, "cam_depth": depth.astype(np.float32) * np.float32(0.001)}
            self.pending = {"ops": [{"op": "set_node_attrs", "node": "kinect", "attrs": attrs}]}
        if self.pending is None or self.in_flight >= 2:
            return
        tx, self.pending = self.pending, None
        self.in_flight += 1

        def written(r) -> None:
            self.in_flight -= 1
            self.written += bool(r.accepted)

        self.camera.send(tx, written)


def hop_costs(repeat: int = 20) -> dict[str, float]:
    """What one hop costs a camera frame (both images) in this process, ms: as JSON text with
    base64 (encode and decode back to arrays), and as blobs beside a small JSON (the bytes copied
    and hashed, the JSON encoded and decoded, the arrays made over the bytes)."""
    from dsr_graph.model.binary import array_coercer, dumps
    from dsr_graph.protocol.blobs import extract, resolve

    rgb = np.random.default_rng(1).integers(0, 256, (480, 640, 3), dtype=np.uint8)
    depth = np.full((480, 640), 1.5, dtype=np.float32)
    delta = {
        "ops": [
            {"op": "set_node_attrs", "node": "k", "attrs": {"cam_rgb": rgb, "cam_depth": depth}}
        ]
    }
    times: dict[str, list[float]] = {"inline_ms": [], "blob_ms": []}
    for _ in range(repeat):
        t0 = time.perf_counter()
        doc = json.loads(dumps(delta))
        attrs = doc["ops"][0]["attrs"]
        array_coercer("uint8_array")(attrs["cam_rgb"])
        array_coercer("float32_array")(attrs["cam_depth"])
        t1 = time.perf_counter()
        out, blobs = extract(delta)
        doc = resolve(json.loads(dumps(out)), blobs.get)
        t2 = time.perf_counter()
        times["inline_ms"].append((t1 - t0) * 1e3)
        times["blob_ms"].append((t2 - t1) * 1e3)
    text = len(dumps(delta))
    return {k: sorted(v)[len(v) // 2] for k, v in times.items()} | {"inline_json_bytes": text}
