"""Real processes for ROS tests: each test gets its own ROS_DOMAIN_ID (and localhost-only
discovery), every process is started in its own process group, every wait is bounded, and
everything started is stopped at teardown (SIGINT, then SIGKILL)."""

import itertools
import json
import os
import shutil
import signal
import subprocess
import time
from pathlib import Path

from dsr_graph.ros import domains, shm_zombies
from dsr_graph.ros.session import RosSession

_next = itertools.count()
_domains: list[int] = []  # this run's block of domains
_locks: list = []  # its lock files, held while we run


def fresh_domain_id() -> int:
    """A ROS domain for one test: the next of this run's own block (ros/domains.py: locked, so
    two test runs, a benchmark or a launch on one machine never share a domain); tests of one
    run take the block's ten in turn, each test having stopped what it started before the next
    begins."""
    if not _domains:
        taken, locks = domains.reserve()
        _domains.extend(taken)
        _locks.extend(locks)
        # Fast DDS ports an earlier run's killed processes left in these domains
        shm_zombies.clean(own_domains())
    return _domains[next(_next) % len(_domains)]


def own_domains() -> list[int]:
    """The domains this process has taken for its tests (none before its first test's)."""
    return list(_domains)


class Processes:
    def __init__(self, workdir: Path, domain_id: int):
        self.workdir = Path(workdir)
        self.domain_id = domain_id
        self.procs = {}

    def env(self, **extra):
        env = os.environ.copy()
        env["ROS_DOMAIN_ID"] = str(self.domain_id)
        env["ROS_AUTOMATIC_DISCOVERY_RANGE"] = "LOCALHOST"
        env["PYTHONUNBUFFERED"] = "1"
        env.update({k: str(v) for k, v in extra.items()})
        return env

    def start(self, name, argv, **env):
        exe = shutil.which(argv[0])
        assert exe, f"{argv[0]} is not on PATH: run the tests through scripts/test.sh"
        log = open(self.workdir / f"{name}.log", "ab")
        proc = subprocess.Popen(
            [exe, *map(str, argv[1:])],
            stdout=log,
            stderr=subprocess.STDOUT,
            env=self.env(**env),
            start_new_session=True,
        )
        self.procs[name] = proc
        return proc

    def start_server(self, state_dir, world=None, name="server", **params):
        args = ["dsr_server", "--ros-args", "-p", f"state_dir:={state_dir}"]
        if world:
            args += ["-p", f"world_file:={world}"]
        for key, value in params.items():
            args += ["-p", f"{key}:={value}"]
        return self.start(name, args)

    def run(self, *argv, timeout=30, input=None, **env):
        """Run a command to completion (e.g. `dsr apply`), bounded; ``env``: more variables."""
        return subprocess.run(
            [shutil.which(argv[0]), *map(str, argv[1:])],
            capture_output=True,
            text=True,
            env=self.env(**env),
            timeout=timeout,
            input=input,
        )

    def log(self, name):
        path = self.workdir / f"{name}.log"
        return path.read_text(errors="replace") if path.exists() else ""

    def tails(self, lines=40):
        """The last ``lines`` of every process log the test wrote (killed processes' too)."""
        parts = []
        for path in sorted(self.workdir.glob("*.log")):
            tail = path.read_text(errors="replace").splitlines()[-lines:]
            parts.append(f"----- {path.name} (last {len(tail)} lines)\n" + "\n".join(tail))
        return "\n".join(parts)

    def kill9(self, name):
        proc = self.procs.pop(name)
        os.killpg(proc.pid, signal.SIGKILL)
        proc.wait(timeout=10)

    def stop(self, name, timeout=10):
        proc = self.procs.pop(name)
        if proc.poll() is None:
            os.killpg(proc.pid, signal.SIGINT)
            try:
                proc.wait(timeout=timeout)
            except subprocess.TimeoutExpired:
                os.killpg(proc.pid, signal.SIGKILL)
                proc.wait(timeout=10)
        return proc.returncode

    def stop_all(self):
        for name in list(self.procs):
            try:
                self.stop(name, timeout=5)
            except ProcessLookupError:
                pass


def wait_for(predicate, timeout, what, session=None):
    """Poll ``predicate`` (spinning ``session`` if given) until true; AssertionError after
    ``timeout``."""
    deadline = time.monotonic() + timeout
    while not predicate():
        if time.monotonic() >= deadline:
            raise AssertionError(f"timed out after {timeout} s waiting for {what}")
        if session is not None:
            session.executor.spin_once(timeout_sec=0.05)
        else:
            time.sleep(0.05)


def snapshot_via(session, timeout=15):
    """The server's snapshot, without its signature (when it signs)."""
    from dsr_graph.protocol.signing import MARK
    from dsr_msgs.srv import GetSnapshot

    client = session.node.create_client(GetSnapshot, "dsr/get_snapshot")
    try:
        text = session.call(client, GetSnapshot.Request(), timeout, "a snapshot").snapshot_json
        cut = text.rfind(MARK)
        return json.loads(text if cut < 0 else text[:cut] + "}")
    finally:
        session.node.destroy_client(client)


def new_session(domain_id, name="test_client"):
    os.environ["ROS_AUTOMATIC_DISCOVERY_RANGE"] = "LOCALHOST"
    return RosSession(name=name, domain_id=domain_id)


def start_synced(ros, cortex_dir=None, world="Robot_viriato.json", **params):
    """A DSR server of the test's own (a CORTEX world from ``cortex_dir``, or empty), and its
    first snapshot: (its state folder, the snapshot)."""
    state = ros.tmp / "state"
    ros.procs.start_server(state, world=(cortex_dir / world) if cortex_dir else None, **params)
    return state, snapshot_via(ros.session, timeout=20)


def agent_in_session(ros, timeout=15):
    """A DsrAgent in the test's own ROS session, synced and matched both ways."""
    from dsr_graph.ros.agent import DsrAgent

    agent = DsrAgent(describe=False)  # the test's own client: a tool, not one of the agents
    agent.setup(ros.session.node, timeout_sec=timeout)
    wait_for(lambda: agent.ready, timeout, "the agent to sync", ros.session)
    return agent


def agent_on_node(ros, name, blobs=False, describe=True, timeout=15):
    """A DsrAgent on a node of its own, ``name``, in the test's session, synced and matched
    (``describe``: it keeps an agent info node, as the robot's agents do)."""
    import rclpy

    from dsr_graph.ros.agent import DsrAgent

    node = rclpy.create_node(name, context=ros.session.context)
    ros.session.executor.add_node(node)
    agent = DsrAgent(blobs=blobs, describe=describe)
    agent.setup(node, timeout_sec=timeout)
    wait_for(lambda: agent.ready, timeout, f"{name} to sync", ros.session)
    return agent


def send_and_wait(ros, agent, doc, timeout=20):
    """Send a transaction and spin until its verdict (a dsr_graph.agent.Result). The bound is
    beyond the server's own wait for a sender's node name (identity.NODE_INFO_WAIT, 10 s), which
    a just restarted server may need."""
    results = []
    agent.send(doc, results.append)
    wait_for(lambda: results, timeout, "a verdict", ros.session)
    return results[0]


def _ends(text: str, head: int = 800, tail: int = 1500) -> str:
    """A log's start and end: a node's first lines say how far it got, and a flood of one error
    (Fast DDS's) must not hide them."""
    if len(text) <= head + tail:
        return text
    return f"{text[:head]}\n[... {len(text) - head - tail} characters ...]\n{text[-tail:]}"


def run_robot(script, *args, run_dir, timeout=240, env=None):
    """Run one of the README's scripts (launch.sh, two_hosts.sh) with ``--run-dir run_dir`` in a
    ROS domain of its own, bounded; asserts it exited 0, showing its output and the start and end
    of every log of the run if not. Returns the finished process."""
    repo = Path(__file__).resolve().parents[1]
    env = env or dict(os.environ, ROS_DOMAIN_ID=str(fresh_domain_id()))
    argv = [str(repo / "scripts" / script), *map(str, args), "--run-dir", str(run_dir)]
    proc = subprocess.Popen(
        argv, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=env
    )
    try:
        out, err = proc.communicate(timeout=timeout)
    except subprocess.TimeoutExpired:  # stopped as a user would (Ctrl-C), showing how far it got
        proc.send_signal(signal.SIGINT)
        try:
            out, err = proc.communicate(timeout=30)
        except subprocess.TimeoutExpired:
            proc.kill()
            out, err = proc.communicate()
        err = f"{err}\n[test] {script} still ran after {timeout} s: interrupted\n"
        proc.returncode = proc.returncode or -1
    done = subprocess.CompletedProcess(argv, proc.returncode, out, err)
    if done.returncode != 0:
        logs = "\n".join(
            f"--- {p.name}\n{_ends(p.read_text(errors='replace'))}"
            for p in sorted((Path(run_dir) / "log").glob("*.log"))
        )
        raise AssertionError(done.stdout[-4000:] + done.stderr[-2000:] + logs)
    return done


# the viewer's and the dashboard's ports, chosen by the system: a test's launch never meets a
# robot (or another test) the machine runs on the default ones
EPHEMERAL_PORTS = ("--viewer-port", "0", "--dashboard-port", "0")


def launch_scenario(scenario, tmp_path, *extra, wall=240):
    """``scripts/launch.sh --scenario SCENARIO`` in a ROS domain of its own, storing in a fresh
    database under ``tmp_path``: (the finished launch, what it stored). ``wall``: seconds the
    launch may take in all, more than its own ``--timeout`` (150 unless ``extra`` says)."""
    db = tmp_path / "cgamed.sqlite"
    env = dict(os.environ, ROS_DOMAIN_ID=str(fresh_domain_id()))
    run = run_robot(
        "launch.sh",
        "--scenario",
        scenario,
        "--db",
        db,
        "--timeout",
        "150",
        *EPHEMERAL_PORTS,
        *extra,
        run_dir=tmp_path / "run",
        timeout=wall,
        env=env,
    )
    return run, stored_tests(db, env)


def stored_tests(db, env=None) -> list[dict]:
    """What ``clarc results --db DB --json`` lists: the tests CGAmed stored, oldest first."""
    listed = subprocess.run(
        ["clarc", "results", "--db", str(db), "--json"],
        capture_output=True,
        text=True,
        timeout=60,
        env=env,
        check=True,
    )
    return json.loads(listed.stdout)
