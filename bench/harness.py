"""What every benchmark section uses: processes in a ROS domain of their own, replicas, percentiles,
CPU and memory readings, busy cores."""

from __future__ import annotations

import contextlib
import os
import shutil
import signal
import statistics
import subprocess
import sys
import time
from pathlib import Path
from typing import Any

from dsr_graph.ros.agent import DsrAgent
from dsr_graph.ros.dsr_node import DsrNode
from dsr_graph.ros.session import RosSession

ROOT = Path(__file__).resolve().parent.parent


HERE = Path(__file__).resolve().parent


# ---------------------------------------------------------------------------- processes
class Procs:
    def __init__(self, workdir: Path, domain: int):
        self.workdir, self.domain, self.procs = workdir, domain, []
        self.env = dict(
            os.environ,
            ROS_DOMAIN_ID=str(domain),
            ROS_AUTOMATIC_DISCOVERY_RANGE="LOCALHOST",
            PYTHONUNBUFFERED="1",
        )

    def start(
        self, name: str, argv: list[str], stdin: Any = subprocess.DEVNULL
    ) -> subprocess.Popen:
        exe = shutil.which(argv[0]) or argv[0]
        p = subprocess.Popen(
            [exe, *argv[1:]],
            stdin=stdin,
            stdout=subprocess.PIPE,
            stderr=open(self.workdir / f"{name}.log", "w"),
            env=self.env,
            text=True,
            start_new_session=True,
        )
        self.procs.append(p)
        return p

    def server(self, state: Path, world: str = "") -> subprocess.Popen:
        args = [
            "dsr_server",
            "--ros-args",
            "-p",
            f"state_dir:={state}",
            "-p",
            "publish_poses:=false",
        ]
        if world:
            args += ["-p", f"world_file:={world}"]
        return self.start("server", args)

    def __enter__(self) -> Procs:
        return self

    def __exit__(self, *exc: Any) -> None:
        self.stop_all()

    def stop_all(self) -> None:
        for p in self.procs:
            if p.poll() is None:
                os.killpg(p.pid, signal.SIGINT)
        for p in self.procs:
            try:
                p.wait(timeout=10)
            except subprocess.TimeoutExpired:
                os.killpg(p.pid, signal.SIGKILL)
                p.wait()
        self.procs = []


def percentiles(xs: list[float]) -> dict[str, float]:
    xs = sorted(xs)
    pick = lambda q: xs[min(len(xs) - 1, int(q * len(xs)))]  # noqa: E731
    return {
        "p50_ms": pick(0.5) * 1e3,
        "p90_ms": pick(0.9) * 1e3,
        "p99_ms": pick(0.99) * 1e3,
        "n": len(xs),
    }


def rss_kib(pid: int) -> int:
    for line in open(f"/proc/{pid}/status"):
        if line.startswith("VmRSS:"):
            return int(line.split()[1])
    return 0


def session_with_agent(domain: int, name: str):
    """A session whose node ``name`` has a DSR replica, synced: (session, agent), spun as the
    robot's agents are (DsrNode.EXECUTOR). The caller closes the session (``agent_session``
    does)."""
    ros = RosSession(name=name, domain_id=domain, executor=DsrNode.EXECUTOR)
    try:
        agent = DsrAgent()
        agent.setup(ros.node, timeout_sec=60)
        ros.spin_until(lambda: agent.ready, 60, "the server")
    except BaseException:
        ros.close()  # its node would stay in the domain: the section's next agent of that name
        raise
    return ros, agent


@contextlib.contextmanager
def agent_session(domain: int, name: str):
    """``session_with_agent`` closed when the block ends, however it ends."""
    ros, agent = session_with_agent(domain, name)
    try:
        yield ros, agent
    finally:
        ros.close()


def extra_agent(ros, name: str) -> DsrAgent:
    """Another node in ``ros`` with a DSR replica of its own, synced."""
    node = __import__("rclpy").create_node(name, context=ros.context)
    ros.executor.add_node(node)
    agent = DsrAgent()
    agent.setup(node, timeout_sec=30)
    ros.spin_until(lambda: agent.ready, 30, name)
    return agent


def timed_reader(ros, name: str = "bench_reader"):
    """A second node in ``ros`` with a DSR replica: (node, agent, {delta id: when it arrived})."""
    reader = extra_agent(ros, name)
    reader_node = reader.node
    arrived: dict[str, float] = {}
    reader.add_listener(
        lambda deltas, _: arrived.update({d["id"]: time.perf_counter() for d in deltas})
    )
    return reader_node, reader, arrived


def median_ms(xs: list[float]) -> float:
    return statistics.median(xs) * 1e3


# ---------------------------------------------------------------------------- 2. throughput
def _wait_ready(p: subprocess.Popen, timeout: float = 60, word: str = "ready") -> None:
    """Read ``p``'s output until a line says ``word`` (a helper process's own waits are
    bounded: it says it or ends)."""
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        line = p.stdout.readline()
        if line.strip() == word:
            return
        if not line and p.poll() is not None:
            raise RuntimeError(f"a helper process ended before it said {word!r}")
    raise RuntimeError(f"a helper process did not say {word!r} in time")


# ---------------------------------------------------------------------------- 6. get up & go
def cpu_seconds(pid: int) -> float:
    fields = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")


def latency_samples(ros, writer, arrived, n: int, change, step=lambda: None) -> list[float]:
    """Seconds from sending ``change(i)`` until the reader's replica applied it, for i < n, the
    first tenth left out (warming up); ``step`` runs while waiting (another stream)."""
    samples = []
    for i in range(n):
        tx = change(i)
        sent = time.perf_counter()
        ident = writer.send(tx)
        while ident not in arrived:  # the stream goes on while we wait
            step()
            ros.executor.spin_once(timeout_sec=0.0005)
            if time.perf_counter() - sent > 10:
                raise RuntimeError("a change was not seen within 10 s")
        samples.append(arrived[ident] - sent)
    return samples[n // 10 :]


@contextlib.contextmanager
def busy_cores(count: int):
    """``count`` processes spinning on a core each, for as long as the block runs."""
    spinners = [
        subprocess.Popen([sys.executable, "-c", "while True: pass"], start_new_session=True)
        for _ in range(count)
    ]
    try:
        yield
    finally:
        for p in spinners:
            p.kill()
            p.wait()


def server_cpu(server, ros, seconds: float, run) -> float:
    """The server's share of a core while ``run()`` is called for ``seconds``."""
    before, t0 = cpu_seconds(server.pid), time.perf_counter()
    while time.perf_counter() - t0 < seconds:
        run()
        ros.executor.spin_once(timeout_sec=0.001)
    return (cpu_seconds(server.pid) - before) / (time.perf_counter() - t0)


def speech_change(i: int) -> dict[str, Any]:
    """A Speech-sized change."""
    return {"ops": [{"op": "set_node_attrs", "node": "test", "attrs": {"item": f"x{i}"}}]}


# ---------------------------------------------------------------------------- 7. signed
@contextlib.contextmanager
def environment(**values: str | None):
    """These environment variables (None: unset) for this process and the ones it starts, for
    the block; then as before."""
    saved = {k: os.environ.get(k) for k in values}
    for k, v in values.items():
        if v is None:
            os.environ.pop(k, None)
        else:
            os.environ[k] = v
    try:
        yield
    finally:
        for k, v in saved.items():
            if v is None:
                os.environ.pop(k, None)
            else:
                os.environ[k] = v


def security(mode: str, keystore: Path):
    """DSR_SECURITY (and DSR_KEYSTORE) for this process and the ones it starts, then as before."""
    return environment(DSR_SECURITY=mode, DSR_KEYSTORE=None if mode == "off" else str(keystore))
