"""Change-to-visible latency over two hops: a symbolic change (journalled: broadcast at once, its
writer told once a group commit made it durable) and a volatile one, next to a raw rclpy relay
in interleaved rounds, and the fdatasync of a journal line on this disk; where the time of one
change goes."""

from __future__ import annotations

import contextlib
import json
import os
import select
import sys
import time
from pathlib import Path
from typing import Any

from harness import (
    HERE,
    Procs,
    _wait_ready,
    environment,
    median_ms,
    percentiles,
    session_with_agent,
)
from rounds import interleave, pooled, ratio
from std_msgs.msg import String

from dsr_graph.ros.qos import qos_stream


# ---------------------------------------------------------------------------- 1. latency
class LatencyRig:
    """A DSR server and a raw rclpy relay side by side in one domain, a writer in this process
    and the timed reader in a process of its own (remote_reader.py), as a reading agent is on
    the robot: each side of the latency ratios sampled on demand, so that rounds of them can be
    interleaved (rounds.py). Until 2026-12-07 the reader was a second node in this process: the
    writer's replica and its durable notices then shared one executor with the reader's, and
    the reader's callback waited its turn (0.25 ms of a change's 0.64 in one run's stages)."""

    def __init__(self, procs: Procs, work: Path, domain: int, tag: str = ""):
        """``tag``: what this rig's files and node names end with (two rigs in one process)."""
        procs.server(work / f"lat_state{tag}")
        # baseline: the same payload through a raw rclpy relay, same hops, same QoS
        procs.start(
            f"relay{tag}", [sys.executable, str(HERE / "relay.py"), "bench/in", "bench/out"]
        )
        self.ros, self.writer = session_with_agent(domain, f"bench_writer{tag}")
        self.tag = tag
        self.arrived: dict[str, float] = {}  # delta id -> when the reader's replica applied it
        self.started: dict[str, float] = {}  # and when its callback took the delta
        self.got: list[float] = []  # when the relayed messages reached the reader
        reader = procs.start(
            f"reader{tag}",
            [sys.executable, str(HERE / "remote_reader.py"), str(domain), f"bench_reader{tag}"]
            + ["bench/out"],
        )
        _wait_ready(reader)
        self._from_reader = reader.stdout.fileno()
        os.set_blocking(self._from_reader, False)
        self._partial = b""
        done: list = []
        self.writer.send(
            {
                "ops": [
                    {"op": "insert_node", "name": "bench", "type": "transform"},
                    # a sensor's node: its frame_time is volatile (not journalled)
                    {"op": "insert_node", "name": "bench_sensor", "type": "person"},
                ]
            },
            done.append,
        )
        self.ros.spin_until(lambda: done, 10, "set-up")
        self.payload = json.dumps(dict(change(0), id=self.writer.next_id(), agent=self.writer.name))
        self.pub = self.ros.node.create_publisher(String, "bench/in", qos_stream())
        self.ros.spin_until(lambda: self.pub.get_subscription_count() > 0, 30, "the relay")
        self.ros.spin_for(0.5)
        self.sent = 0  # every change sets a value not set before
        self.publish: list[float] = []  # the raw side's publish calls (seconds)

    def _heard(self) -> bool:
        """Take what the reader process wrote so far (never waits); whether it wrote anything."""
        try:
            data = os.read(self._from_reader, 65536)
        except BlockingIOError:
            return False
        if not data:
            raise RuntimeError(f"the reader process ended (its log: reader{self.tag}.log)")
        *lines, self._partial = (self._partial + data).split(b"\n")
        for line in lines:
            kind, *fields = line.decode().split()
            if kind == "d":
                self.arrived[fields[0]] = float(fields[1])
                self.started[fields[0]] = float(fields[2])
            elif kind == "r":
                self.got.append(float(fields[0]))
        return True

    def _changes(self, make, n: int) -> list[float]:
        first, self.sent = self.sent, self.sent + n
        return [self.arrived[ident] - sent for ident, sent, _ in self._timed(make, first, n)]

    def _timed(self, make, first: int, n: int) -> list[tuple[str, float, float]]:
        """(id, when it was sent, when the writer's send returned) of n changes, the first
        tenth left out (warming up). This process waits for the reader without spinning, as the
        raw side does (a writer on the robot is not the reader's process); then, outside the
        timing, it lets the writer take its own delta and its verdict before the next change."""
        # what came while this process waited (the other side's round, another rig's): a
        # writer that heard no heartbeat for SERVER_SILENCE holds its requests until it does
        self.ros.spin_for(0.1)
        out = []
        for i in range(first, first + n):
            verdict: list = []
            sent = time.perf_counter()
            ident = self.writer.send(make(i), verdict.append)
            published = time.perf_counter()
            self._wait_reader(lambda ident=ident: ident in self.arrived, sent, "a change")
            out.append((ident, sent, published))
            self.ros.spin_until(lambda verdict=verdict: verdict, 10, "the writer's verdict")
        return out[n // 10 :]

    def _wait_reader(self, seen, since: float, what: str) -> None:
        while not seen():
            select.select([self._from_reader], [], [], 0.05)
            if not self._heard() and time.perf_counter() - since > 10:
                raise RuntimeError(f"{what} was not seen by the reader within 10 s")

    def symbolic(self, n: int) -> list[float]:
        """A symbolic change (journalled by a group commit after it is broadcast), n times."""
        return self._changes(change, n)

    def volatile(self, n: int) -> list[float]:
        """A sensor's volatile value (not journalled), n times."""
        return self._changes(reading, n)

    def raw(self, n: int) -> list[float]:
        """The same payload through the relay to the reader's node, n times."""
        samples, publish = [], []
        for _ in range(n):
            before = len(self.got)
            sent = time.perf_counter()
            self.pub.publish(String(data=self.payload))
            publish.append(time.perf_counter() - sent)
            self._wait_reader(lambda before=before: len(self.got) > before, sent, "a message")
            samples.append(self.got[-1] - sent)
        self.publish += publish[n // 10 :]
        return samples[n // 10 :]


def change(i: int) -> dict[str, Any]:
    return {"ops": [{"op": "set_node_attrs", "node": "bench", "attrs": {"level": i}}]}


def reading(i: int) -> dict[str, Any]:
    attrs = {"frame_time": float(i)}
    return {"ops": [{"op": "set_node_attrs", "node": "bench_sensor", "attrs": attrs}]}


@contextlib.contextmanager
def latency_rig(work: Path, domain: int, tag: str = ""):
    procs = Procs(work, domain)
    try:
        rig = LatencyRig(procs, work, domain, tag)
        try:
            yield rig
        finally:
            rig.ros.close()
    finally:
        procs.stop_all()


def bench_latency(work: Path, domain: int, rounds: int, per_round: int) -> dict[str, Any]:
    """Change-to-visible latency of a symbolic and a volatile change and of the raw relay, in
    ``rounds`` interleaved rounds of ``per_round`` samples; where the time of one goes; the
    fdatasync of a journal line on this disk."""
    with latency_rig(work, domain) as rig:
        runs = interleave(
            {
                "dsr": lambda r: rig.symbolic(per_round),
                "volatile": lambda r: rig.volatile(per_round),
                "raw": lambda r: rig.raw(per_round),
            },
            rounds,
        )
        # where the time goes: the same changes again, each step timed (a profile of one run)
        stages = {
            "symbolic": latency_stages(rig, per_round, change),
            "volatile": latency_stages(rig, per_round, reading),
        }
        stages["raw"] = {"publish_ms": median_ms(rig.publish)}
        payload = rig.payload
    n = rounds * per_round // 2
    fdatasync = percentiles(fdatasync_samples(work / "fdatasync_probe", payload, n))
    # as the server meets it: after a wait for the next request, not back to back
    fdatasync_paced = percentiles(
        fdatasync_samples(work / "fdatasync_probe", payload, n, pause=0.001)
    )
    dsr, volatile, raw = (pooled(runs[k]) for k in ("dsr", "volatile", "raw"))
    stages["raw"]["relay_and_wire_ms"] = raw["p50_ms"] - stages["raw"]["publish_ms"]
    ratios = {
        "dsr_vs_raw_p50": ratio(runs["dsr"], runs["raw"], "p50_ms"),
        "dsr_vs_raw_p99": ratio(runs["dsr"], runs["raw"], "p99_ms"),
        "volatile_vs_raw_p50": ratio(runs["volatile"], runs["raw"], "p50_ms"),
    }
    floor = raw["p50_ms"] + fdatasync["p50_ms"]  # a relay that also writes to the disk
    r50, r99, v50 = (ratios[k]["median"] for k in ratios)
    return {
        "dsr": dsr,
        "volatile": volatile,
        "raw": raw,
        "fdatasync": fdatasync,
        "fdatasync_paced": fdatasync_paced,
        "stages": stages,
        "payload_bytes": len(payload),
        "rounds": {"count": rounds, "samples_per_round": per_round},
        "ratios": ratios,
        # the medians of the per-round ratios
        "ratio_p50": r50,
        "ratio_p99": r99,
        "ratio_p50_durable_floor": dsr["p50_ms"] / floor,
        "ratio_p50_volatile": v50,
        "targets": "symbolic p50 <= 1.3x raw, p99 <= 1.5x raw; volatile p50 <= 1.15x raw "
        "(medians of the per-round ratios)",
        "met": r50 <= 1.3 and r99 <= 1.5 and v50 <= 1.15,
    }


def fdatasync_samples(path: Path, payload: str, n: int, pause: float = 0.0) -> list[float]:
    """Seconds to append ``payload`` as a line and fdatasync it, as the journal does, n times
    (on the bench's own disk, in this run), back to back or ``pause`` s apart."""
    samples = []
    line = (payload + "\n").encode()
    with open(path, "ab") as f:
        for _ in range(n):
            if pause:
                time.sleep(pause)
            t = time.perf_counter()
            f.write(line)
            f.flush()
            os.fdatasync(f.fileno())
            samples.append(time.perf_counter() - t)
    path.unlink()
    return samples[n // 10 :]


def latency_stages(rig: LatencyRig, n: int, change) -> dict[str, float]:
    """Medians (ms) of each step of a change, n changes: the writer's send (encode, sign,
    publish); from its end to the start of the reader's delta callback (both hops, the server,
    the reader's wake-up); the reader's callback (parse, apply, listeners); send to applied."""
    rows = [
        {
            "send_ms": published - sent,
            "server_and_wire_ms": rig.started[ident] - published,
            "reader_replica_ms": rig.arrived[ident] - rig.started[ident],
            "total_ms": rig.arrived[ident] - sent,
        }
        for ident, sent, published in rig._timed(change, 10**6, n)
    ]
    return {key: median_ms([r[key] for r in rows]) for key in rows[0]}


def servers_from(tree: Path):
    """Processes started in the block run the dsr_graph of another source tree (its
    ``src/dsr_graph`` first on PYTHONPATH); this process's agents keep this tree's."""
    return environment(
        PYTHONPATH=f"{tree / 'src' / 'dsr_graph'}:{os.environ.get('PYTHONPATH', '')}"
    )


def bench_server_against(
    work: Path, domain: int, rounds: int, per_round: int, baseline: Path
) -> dict[str, Any]:
    """This tree's server against ``baseline``'s (another source tree of the project), side by
    side in two domains with the same agents' code, a symbolic and a volatile change each in
    interleaved rounds: to tell whether a change to the server pays, in one run."""
    with contextlib.ExitStack() as stack:
        head = stack.enter_context(latency_rig(work, domain, tag="_head"))
        with servers_from(baseline):
            base = stack.enter_context(latency_rig(work, domain + 1, tag="_base"))
        runs = interleave(
            {
                "head": lambda r: head.symbolic(per_round),
                "baseline": lambda r: base.symbolic(per_round),
                "head_volatile": lambda r: head.volatile(per_round),
                "baseline_volatile": lambda r: base.volatile(per_round),
            },
            rounds,
        )
    return {key: pooled(samples) for key, samples in runs.items()} | {
        "ratios": {
            "head_vs_baseline_p50": ratio(runs["head"], runs["baseline"], "p50_ms"),
            "head_vs_baseline_p99": ratio(runs["head"], runs["baseline"], "p99_ms"),
            "head_vs_baseline_volatile_p50": ratio(
                runs["head_volatile"], runs["baseline_volatile"], "p50_ms"
            ),
        }
    }
