"""The real ``ros2`` command line (ros2cli, Jazzy) on a running DSR, as
docs/how-to/jazzy-install.md tells users:
``ros2 run`` with ``--ros-args -p``, ``ros2 node list``, ``ros2 topic list -t``, ``ros2 topic
echo``, ``ros2 topic pub`` of a transaction (signed with the keystore, and forged),
``ros2 service call`` of each dsr_msgs service, ``ros2 param list/get/set``, ``ros2 interface
show``, and ``ros2 run <pkg> <exe> --help`` for every console script. Every listing command runs
with ``--no-daemon``: the test leaves no ros2 daemon behind."""

import json
import re
import subprocess
import time
from pathlib import Path

import pytest
import yaml
from package_scripts import console_scripts

from dsr_graph.formats.keystore import Keystore
from dsr_graph.protocol.signing import Signer

from ros_processes import wait_for

REPO = Path(__file__).resolve().parents[2]
WORLD_CLARC = REPO / "worlds" / "clarc_room.json"
WAIT = 60  # seconds any one command may take on a busy machine


def ros2(ros, *args, timeout=WAIT, check=True):
    """``ros2 ARGS``, bounded. A command that looks a node up (param) without the daemon sees
    only what its own fresh node discovered in its spin time (0.5 s): on a busy machine it may
    say "Node not found" of a node that is there; it is run again then, within ``timeout``."""
    deadline = time.monotonic() + timeout
    while True:
        done = ros.procs.run("ros2", *args, timeout=timeout)
        if "Node not found" not in done.stderr or time.monotonic() >= deadline:
            break
        time.sleep(0.5)
    if check:
        assert done.returncode == 0, f"ros2 {' '.join(map(str, args))}: {done.stdout}{done.stderr}"
    return done


def until_listed(ros, args, wanted, what):
    """``ros2 <args>`` run again until its output holds every string of ``wanted`` (discovery
    takes its time on a busy machine); bounded."""
    deadline = time.monotonic() + WAIT
    while True:
        out = ros2(ros, *args).stdout
        missing = [w for w in wanted if w not in out]
        if not missing:
            return out
        if time.monotonic() >= deadline:
            raise AssertionError(f"{what}: {missing} not in the output of ros2 {args}:\n{out}")
        time.sleep(0.5)


class Echo:
    """``ros2 topic echo TOPIC --once`` in the background, started before what it should see."""

    def __init__(self, ros, topic):
        before = ros.session.node.count_subscribers(topic)
        self.name = f"echo{topic.replace('/', '_')}"
        self.proc = ros.procs.start(
            self.name,
            [
                *("ros2", "topic", "echo", topic, "std_msgs/msg/String"),
                *("--once", "--full-length", "--no-daemon"),
            ],
        )
        wait_for(
            lambda: ros.session.node.count_subscribers(topic) > before,
            WAIT,
            f"ros2 topic echo to subscribe to {topic}",
            ros.session,
        )
        self.ros = ros

    def message(self):
        self.proc.wait(timeout=WAIT)
        text = self.ros.procs.log(self.name)
        return yaml.safe_load(text.split("\n---")[0])["data"]


def pub(ros, node, text):
    """``ros2 topic pub --once`` of ``text`` on ``node``'s request topic, as node ``node``."""
    return ros2(
        ros,
        "topic",
        "pub",
        "--once",
        "--keep-alive",
        "3",
        "-n",
        node,
        f"/dsr/transactions/{node}",
        "std_msgs/msg/String",
        yaml.safe_dump({"data": text}, width=10**6),
    )


def test_ros2_command_line_on_a_running_dsr(ros, ros2_cli, monkeypatch):
    ks, _ = Keystore.init(ros.tmp / "ks")
    for name in ("/test_client", "/tester"):
        ks.add(name)
    monkeypatch.setenv("DSR_KEYSTORE", str(ks.root))  # enforce: every process of this test
    ros.procs.start(
        "server",
        [
            *("ros2", "run", "dsr_graph", "dsr_server", "--ros-args"),
            *("-p", f"state_dir:={ros.tmp / 'state'}", "-p", f"world_file:={WORLD_CLARC}"),
            *("-p", "compact_every:=50"),
        ],
    )
    until_listed(ros, ("node", "list", "--no-daemon"), ["/dsr_server"], "the server's node")
    topics = until_listed(
        ros,
        ("topic", "list", "-t", "--no-daemon"),
        [
            "/dsr/deltas [std_msgs/msg/String]",
            "/dsr/heartbeat [std_msgs/msg/String]",
            "/dsr/alarms [std_msgs/msg/String]",
            "/dsr/blobs [dsr_msgs/msg/Blob]",
            "/tf_static [tf2_msgs/msg/TFMessage]",
            "/dsr/markers [visualization_msgs/msg/MarkerArray]",
        ],
        "the server's topics",
    )
    assert "/dsr/pose/" in topics

    # a transaction published with ros2 topic pub, signed with /tester's key: applied, and the
    # delta seen by ros2 topic echo
    deltas = Echo(ros, "/dsr/deltas")
    doc = {
        "agent": "/tester",
        "id": "tester:1",
        "ops": [{"op": "set_node_attrs", "node": "panel", "attrs": {"text": "from ros2"}}],
    }
    signed = Signer("/tester", ks.private_key("/tester")).sign("dsr/transactions", json.dumps(doc))
    pub(ros, "tester", signed)
    delta = json.loads(re.sub(r',"sig":\{.*\}\}$', "}", deltas.message()))
    assert delta["agent"] == "/tester" and delta["id"] == "tester:1", delta
    assert delta["ops"][0]["attrs"] == {"text": "from ros2"}

    # the same unsigned: refused, and the server says so on dsr/alarms
    alarms = Echo(ros, "/dsr/alarms")
    pub(ros, "tester", json.dumps(dict(doc, id="tester:2", ops=[dict(doc["ops"][0], attrs={})])))
    alarm = alarms.message()
    assert '"kind":"signature"' in alarm.replace(" ", "") and "/dsr/transactions/tester" in alarm

    # each dsr_msgs service
    got = ros2(
        ros,
        *("service", "call", "/dsr/get_attribute", "dsr_msgs/srv/GetAttribute"),
        "{node: panel, attribute: text}",
    ).stdout
    assert "found=True" in got and "value_json='\"from ros2\"'" in got, got
    got = ros2(
        ros, "service", "call", "/dsr/get_node", "dsr_msgs/srv/GetNode", "{node: panel}"
    ).stdout
    assert "found=True" in got and '"name": "panel"' in got.replace('\\"', '"'), got
    got = ros2(ros, "service", "call", "/dsr/get_snapshot", "dsr_msgs/srv/GetSnapshot", "{}").stdout
    assert re.search(r"seq=[1-9]", got) and "dsr-graph" in got, got
    # (a fresh node lists what it discovered in its spin time: on a busy machine, maybe nothing
    # yet; the server's services are there, the call above answered)
    until_listed(
        ros,
        ("service", "list", "-t", "--no-daemon"),
        [
            "/dsr/get_attribute [dsr_msgs/srv/GetAttribute]",
            "/dsr/get_node [dsr_msgs/srv/GetNode]",
            "/dsr/get_snapshot [dsr_msgs/srv/GetSnapshot]",
            "/dsr/get_transform [dsr_msgs/srv/GetTransform]",
            "/dsr/get_blob [dsr_msgs/srv/GetBlob]",
        ],
        "the server's services",
    )

    # parameters: listed, read, a dynamic one set, a read-only one refused
    listed = ros2(ros, "param", "list", "/dsr_server", "--no-daemon").stdout
    for name in ("compact_every", "state_dir", "agent_grace", "policy_file"):
        assert f"  {name}\n" in listed, listed
    got = ros2(ros, "param", "get", "/dsr_server", "compact_every", "--no-daemon").stdout
    assert got.strip() == "Integer value is: 50", got
    got = ros2(ros, "param", "set", "/dsr_server", "agent_grace", "5.0", "--no-daemon").stdout
    assert got.strip() == "Set parameter successful", got
    got = ros2(ros, "param", "get", "/dsr_server", "agent_grace", "--no-daemon").stdout
    assert got.strip() == "Double value is: 5.0", got
    refused = ros2(
        ros, "param", "set", "/dsr_server", "compact_every", "5", "--no-daemon", check=False
    )
    assert "read-only" in refused.stdout + refused.stderr, refused

    # the interfaces, as ros2 interface shows them
    shown = ros2(ros, "interface", "show", "dsr_msgs/srv/GetAttribute").stdout
    assert "string node" in shown and "---" in shown and "string value_json" in shown, shown
    assert "uint8[] data" in ros2(ros, "interface", "show", "dsr_msgs/msg/Blob").stdout
    packages = ros2(ros, "interface", "packages").stdout.split()
    assert "dsr_msgs" in packages


def test_ros2_run_finds_every_console_script(ros, ros2_cli):
    declared = console_scripts()
    for package in sorted({p for p, _ in declared}):
        listed = ros2(ros, "pkg", "executables", package).stdout.split("\n")
        scripts = sorted(name for p, name in declared if p == package)
        assert sorted(line.split()[1] for line in listed if line) == scripts, listed
        for script in scripts:
            done = ros2(ros, "run", package, script, "--help")
            assert done.stdout.strip(), f"ros2 run {package} {script} --help printed nothing"


@pytest.fixture(autouse=True)
def no_ros2_daemon_left(ros):
    """Fails the test if a ros2 daemon of its domain was left running (one outlives the command
    that starts it: every listing command here says --no-daemon)."""
    yield
    found = subprocess.run(
        ["pgrep", "-af", "--", f"--name ros2-daemon --ros-domain-id {ros.domain_id}( |$)"],
        capture_output=True,
        text=True,
    )
    assert not found.stdout.strip(), f"a ros2 daemon was left running: {found.stdout}"
