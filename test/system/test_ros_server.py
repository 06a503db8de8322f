"""The DSR server and agents as real processes over ROS 2: apply/get/graph/watch/save/ros,
ordering, late join, kill -9 and restart, hostile input, claims, racing rules. What the server
shows ROS tools (poses, tf, markers, echo and param) is test_ros_server_views.py."""

import json
import time
from pathlib import Path

import numpy as np
import pytest
from std_msgs.msg import String

from dsr_graph.formats import dsr_json
from dsr_graph.formats.world_files import read_world
from dsr_graph.ros.agent import DsrAgent
from dsr_graph.ros.qos import qos_stream

from ros_processes import (
    agent_in_session,
    agent_on_node,
    send_and_wait,
    snapshot_via,
    start_synced,
    wait_for,
)


def canonical(doc):
    return json.dumps(doc, sort_keys=True)


@pytest.mark.smoke  # dsr_graph's (scripts/test.sh --quick)
def test_cli_apply_get_graph_save_ros(ros, cortex_dir, tmp_path):
    start_synced(ros, cortex_dir)
    tx = tmp_path / "tx.json"
    tx.write_text(
        json.dumps(
            {
                "ops": [
                    {"op": "insert_node", "name": "speaking", "type": "state"},
                    {"op": "insert_edge", "from": "robot", "to": "speaking", "type": "is_not"},
                ]
            }
        )
    )
    r = ros.procs.run("dsr", "apply", tx)
    assert r.returncode == 0 and r.stdout.strip() == "accepted: seq 1", r.stderr
    r = ros.procs.run("dsr", "apply", tx)
    assert r.returncode == 1 and "unique-name" in r.stdout
    r = ros.procs.run(
        "dsr",
        "apply",
        "-",
        input='{"ops": [{"op": "set_node_attrs", "node": "robot", "attrs": {"level": "x"}}]}',
    )
    assert r.returncode == 1 and "attribute-type" in r.stdout
    r = ros.procs.run("dsr", "get", "robot", "port")
    assert r.returncode == 0 and json.loads(r.stdout) == {
        "value": 12238,
        "type": "int",
        "version": 1,
        "seq": 1,
    }
    r = ros.procs.run("dsr", "get", "robot", "nothing")
    assert r.returncode == 1 and "has no attribute 'nothing'" in r.stderr
    r = ros.procs.run("dsr", "get", "speaking")
    assert json.loads(r.stdout)["in"][0]["type"] == "is_not"
    r = ros.procs.run("dsr", "get", "body", "rt", "--edge", "laser_pose", "RT")
    assert np.allclose(np.array(json.loads(r.stdout)["value"])[:3, 3], [0, 0.4, 0])  # metres
    r = ros.procs.run("dsr", "graph")
    assert (
        r.returncode == 0
        and "seq 1: 15 nodes" in r.stdout
        and "robot -is_not-> speaking" in r.stdout
    )
    r = ros.procs.run("dsr", "save", tmp_path / "saved.json")
    assert r.returncode == 0
    saved = read_world(tmp_path / "saved.json")
    assert saved.violations == [] and "speaking" in saved.graph
    r = ros.procs.run("dsr", "ros", "--json")
    info = json.loads(r.stdout)
    assert "/dsr_server" in info["nodes"]
    topics = {t["name"]: t["types"] for t in info["topics"]}
    assert topics["/dsr/deltas"] == ["std_msgs/msg/String"]
    assert topics["/dsr/pose/laser1"] == ["geometry_msgs/msg/PoseStamped"]
    services = {s["name"]: s["types"] for s in info["services"]}
    assert services["/dsr/get_attribute"] == ["dsr_msgs/srv/GetAttribute"]

    # provenance: who wrote each attribute, and when
    before = time.time()
    r = ros.procs.run(
        "dsr",
        "apply",
        "-",
        input='{"ops": [{"op": "set_node_attrs", "node": "speaking", "attrs": {"color": "red"}}]}',
    )
    assert r.returncode == 0, r.stdout + r.stderr
    r = ros.procs.run("dsr", "get", "speaking", "color", "--provenance")
    written = json.loads(r.stdout)
    assert written["value"] == "red" and written["provenance"]["agent"].startswith("/dsr")
    assert before - 1 <= written["provenance"]["time"] <= time.time() + 1
    assert (
        json.loads(ros.procs.run("dsr", "get", "robot", "port", "--provenance").stdout)[
            "provenance"
        ]
        is None
    )  # from the world file: nobody wrote it since
    whole = json.loads(ros.procs.run("dsr", "get", "speaking", "--provenance").stdout)
    assert whole["provenance"]["color"] == written["provenance"]
    assert "provenance" not in json.loads(ros.procs.run("dsr", "get", "speaking").stdout)


def test_watch_prints_deltas_in_order(ros):
    start_synced(ros)
    watch = ros.procs.start("watch", ["dsr", "watch", "--count", "3", "--duration", "30"])
    agent = agent_in_session(ros)
    # Like `ros2 topic echo`, watch sees what is published once it is matched: keep writing
    # until it has printed three deltas, then check they are consecutive and readable.
    i = 0
    deadline = time.monotonic() + 25
    while watch.poll() is None and time.monotonic() < deadline:
        assert send_and_wait(
            ros, agent, {"ops": [{"op": "insert_node", "name": f"n{i}", "type": "transform"}]}
        ).accepted
        i += 1
        ros.session.spin_for(0.2)
    assert watch.wait(timeout=5) == 0, ros.procs.log("watch")
    lines = ros.procs.log("watch").strip().splitlines()
    seqs = [int(line.split()[1]) for line in lines]
    assert len(seqs) == 3 and seqs == list(range(seqs[0], seqs[0] + 3))
    assert f"+node n{seqs[0] - 1}:transform" in lines[0]


def test_deltas_are_totally_ordered_across_writers_and_replicas_converge(ros):
    start_synced(ros)
    agent = agent_in_session(ros)
    seen = []
    agent.add_listener(lambda deltas, resynced: seen.extend(d["seq"] for d in deltas))
    writer = str(Path(__file__).resolve().parents[1] / "helpers" / "writer.py")
    for prefix in ("a", "b"):  # two writer processes racing this one
        ros.procs.start(f"writer_{prefix}", ["python", writer, prefix, 50])
    for i in range(50):
        agent.send({"ops": [{"op": "insert_node", "name": f"c{i}", "type": "transform"}]})
    wait_for(
        lambda: all(ros.procs.procs[f"writer_{p}"].poll() is not None for p in "ab"),
        60,
        "the writers",
        ros.session,
    )
    assert [ros.procs.log(f"writer_{p}").strip().splitlines()[-1] for p in "ab"] == ["50", "50"]
    wait_for(lambda: agent.replica.seq >= 150, 20, "150 deltas", ros.session)
    # one total order: every replica applies consecutive seqs, never out of order or twice
    assert seen == list(range(seen[0], seen[0] + len(seen))) and seen[-1] == 150
    mine = dsr_json.to_json(agent.graph, "snapshot", seq=agent.replica.seq)
    server = snapshot_via(ros.session)
    server.pop("claims")
    assert canonical(mine) == canonical(server) and len(agent.graph) == 150


def test_late_joiner_gets_the_same_graph(ros, cortex_dir):
    start_synced(ros, cortex_dir, world="autonomyLab_complete.simscene.json")
    early = agent_in_session(ros)
    for i in range(20):
        send_and_wait(
            ros,
            early,
            {
                "ops": [
                    {
                        "op": "set_rt",
                        "from": "world",
                        "to": "Wall2",
                        "rt": {"translation": [i, 0, 0], "rotation_euler_xyz": [0, 0, 0.1 * i]},
                    }
                ]
            },
        )
    # a second replica in the same node, joining now; a test's client, as the early one: one
    # that described itself wrote its info node at a moment of its own, sometimes after "after",
    # and was compared while that change had reached the early replica and not yet the late one
    late = DsrAgent(describe=False)
    late.setup(ros.session.node, timeout_sec=10)
    wait_for(lambda: late.replica.synced, 10, "the late joiner's snapshot", ros.session)
    send_and_wait(
        ros, early, {"ops": [{"op": "insert_node", "name": "after", "type": "transform"}]}
    )
    wait_for(
        lambda: "after" in late.graph and late.replica.seq == early.replica.seq,
        10,
        "the late joiner to follow",
        ros.session,
    )
    assert canonical(dsr_json.to_json(late.graph, "snapshot")) == canonical(
        dsr_json.to_json(early.graph, "snapshot")
    )
    assert np.allclose(late.graph.transform("world", "Wall2")[:3, 3], [19, 0, 0])


def test_kill9_and_restart_loses_no_accepted_change(ros, cortex_dir):
    state, _ = start_synced(ros, cortex_dir, compact_every=7)
    agent = agent_in_session(ros)
    accepted = 0
    for i in range(25):  # crosses several compactions
        accepted += send_and_wait(
            ros, agent, {"ops": [{"op": "insert_node", "name": f"k{i}", "type": "transform"}]}
        ).accepted
    assert accepted == 25
    before = snapshot_via(ros.session)
    ros.procs.kill9("server")
    # another world on that state: refused unless told to resume (test_node_shape), here told
    ros.procs.start_server(state, world=cortex_dir / "Robot_giraff.json", resume="true")
    after = snapshot_via(ros.session, timeout=20)
    assert canonical(after) == canonical(before) and after["seq"] == 25
    wait_for(lambda: agent.ready, 15, "the agent to see the new server", ros.session)
    result = send_and_wait(ros, agent, {"ops": [{"op": "delete_node", "node": "k0"}]})
    assert result.accepted and result.seq == 26
    log = ros.procs.log("server")
    assert "restored" in log and "not loaded (state exists)" in log and "resume:=true" in log


def test_kill9_between_broadcast_and_commit_loses_nothing_acknowledged(ros):
    """The group commit held back 2 s (commit_delay): a change every replica shows, not yet
    durable, dies with the server. Every acknowledged change survives; the replica that saw the
    lost one comes back to the restarted server's graph; its writer, never told it was
    accepted, sends it again and hears once."""
    state, _ = start_synced(ros, commit_delay=2.0)
    writer = agent_in_session(ros)
    observer = agent_on_node(ros, "observer", describe=False)
    kept = send_and_wait(ros, writer, {"ops": [insert("kept")]})
    assert kept.accepted and writer.core.durable >= kept.seq  # heard once it was durable
    verdicts = []
    writer.send({"ops": [insert("lost")]}, verdicts.append)
    wait_for(lambda: "lost" in observer.graph, 10, "the change to be seen", ros.session)
    assert verdicts == [] and observer.core.durable < observer.replica.seq
    assert '"lost"' not in (state / "journal.jsonl").read_text()
    resyncs = observer.resyncs
    ros.procs.kill9("server")  # between the broadcast and the commit

    ros.procs.start_server(state)
    wait_for(lambda: verdicts, 30, "the verdict of the change sent again", ros.session)
    assert [v.accepted for v in verdicts] == [True]
    after = snapshot_via(ros.session, timeout=20)
    names = sorted(n["name"] for n in after["nodes"])
    assert names.count("kept") == 1 and names.count("lost") == 1
    # it held a change the new server never had: a snapshot, not the stale replica, must be
    # what reaches the server's seq (the stale one is already at it: its "lost" came first)
    wait_for(lambda: observer.resyncs > resyncs, 15, "the observer to resync", ros.session)
    wait_for(
        lambda: observer.replica.seq == after["seq"] == writer.replica.seq,
        15,
        "the replicas to reach the server",
        ros.session,
    )
    for replica in (observer, writer):
        assert sorted(n.name for n in replica.graph.nodes()) == names
    assert observer.resyncs > resyncs
    assert '"lost"' in (state / "journal.jsonl").read_text()


def insert(name):
    return {"op": "insert_node", "name": name, "type": "transform"}


def test_kill9_while_sensor_data_streams_loses_no_symbol(ros):
    """Volatile frames (not journalled) stream between symbols; kill -9 mid-stream: every symbol
    accepted comes back, at the same seq, and the stream goes on after the restart."""
    state, _ = start_synced(ros, compact_every=20)
    agent = agent_in_session(ros)
    person = {"translation": [1.0, 0.0, 0.0], "rotation_euler_xyz": [0.0, 0.0, 0.0]}
    setup = [
        {"op": "insert_node", "name": "kinect", "type": "transform"},
        {"op": "insert_node", "name": "person", "type": "person"},
        {"op": "insert_edge", "from": "kinect", "to": "person", "type": "RT", "rt": person},
    ]
    assert send_and_wait(ros, agent, {"ops": setup}).accepted
    verdicts = []

    def frame(i):
        moved = dict(person, translation=[1.0 + i / 1000, 0.0, 0.0])
        return {
            "ops": [
                {"op": "set_rt", "from": "kinect", "to": "person", "rt": moved},
                {"op": "set_node_attrs", "node": "person", "attrs": {"frame_time": float(i)}},
            ]
        }

    for i in range(300):  # a frame each, a symbol every tenth, nothing waited for
        agent.send(frame(i), verdicts.append)
        if i % 10 == 9:
            agent.send(
                {"ops": [{"op": "insert_node", "name": f"s{i}", "type": "transform"}]},
                verdicts.append,
            )
        ros.session.executor.spin_once(timeout_sec=0.001)
    wait_for(lambda: len(verdicts) >= 200, 20, "most verdicts", ros.session)
    ros.procs.kill9("server")
    accepted = [v for v in verdicts if v.accepted]
    frames = [v for v in accepted if "volatile" in v.delta]
    symbols = [v.delta for v in accepted if "volatile" not in v.delta]
    assert frames and symbols and all(d["seq"] > 0 for d in symbols)
    last = max(d["seq"] for d in symbols)
    # each follows a symbol the server broadcast (maybe not durable yet: a frame is not)
    assert all(v.delta["seq"] <= agent.replica.seq for v in frames)
    journal = (state / "journal.jsonl").read_text()
    assert '"volatile"' not in journal and '"frame_time"' not in journal

    ros.procs.start_server(state)
    after = snapshot_via(ros.session, timeout=20)
    names = {n["name"] for n in after["nodes"]}
    made = {op["name"] for d in symbols for op in d["ops"]}
    # (requests the dead server never answered are sent again by the agent: symbols too)
    assert made <= names and after["seq"] >= last
    wait_for(lambda: agent.ready, 15, "the agent to see the new server", ros.session)
    result = send_and_wait(ros, agent, frame(1000))
    assert result.accepted and "volatile" in result.delta
    # its verdict may come before the deltas of the requests sent again (a delta the new server
    # published before it matched us is fetched by a snapshot): the replica catches up
    wait_for(lambda: agent.replica.seq >= result.delta["seq"], 15, "the replica", ros.session)
    assert result.delta["seq"] == agent.replica.seq >= last
    wait_for(
        lambda: agent.graph.node("person").attrs.get("frame_time") == 1000.0,
        10,
        "the stream to go on",
        ros.session,
    )


def test_hostile_messages_get_rejections_and_the_server_stays_up(ros):
    start_synced(ros, max_request_bytes=100000)
    rejections = []
    node = ros.session.node
    node.create_subscription(
        String, "dsr/rejections", lambda m: rejections.append(json.loads(m.data)), qos_stream()
    )
    pub = node.create_publisher(String, "dsr/transactions", qos_stream())
    wait_for(lambda: pub.get_subscription_count() > 0, 10, "the server's subscription", ros.session)
    wait_for(
        lambda: node.count_publishers("dsr/rejections") > 0, 10, "the rejections topic", ros.session
    )
    bad = [
        "",
        "not json",
        "[]",
        "null",
        '{"ops": 5}',
        '{"ops": [{"op": "explode"}]}',
        '{"id": 7, "ops": [{"op": "delete_node"}]}',
        "x" * 200000,
        "[" * 50000 + "]" * 50000,
        '{"ops": [{"op": "insert_node", "name": "a", "type": "robot", "attrs": {"level": 1e999}}]}',
        '{"id": "mine", "ops": [{"op": "delete_node", "node": "nobody"}]}',
    ]
    for text in bad:
        pub.publish(String(data=text))
    wait_for(lambda: len(rejections) >= len(bad), 15, "one rejection per bad message", ros.session)
    assert rejections[-1]["id"] == "mine" and rejections[-1]["reason"]["rule"] == "node-missing"
    assert any(r["reason"]["rule"] == "too-large" for r in rejections)
    assert ros.procs.procs["server"].poll() is None
    assert snapshot_via(ros.session)["seq"] == 0


CLAIMS_POLICY = """
version: 1
agents:  # dsr apply's nodes outrank this test's own node
  - {name: "/dsr_cli_*", priority: 3, nodes: ["*"], edges: ["*"], attributes: ["*"]}
  - {name: "*", priority: 2, nodes: ["*"], edges: ["*"], attributes: ["*"]}
"""


def test_claims_priorities_preemption_and_release_on_death(ros, tmp_path):
    policy = tmp_path / "policy.yaml"
    policy.write_text(CLAIMS_POLICY)
    start_synced(ros, agent_grace=0.5, heartbeat_period=0.2, policy_file=policy)
    agent = agent_in_session(ros)
    assert send_and_wait(
        ros,
        agent,
        {
            "ops": [
                {"op": "insert_node", "name": "person", "type": "person"},
                {"op": "insert_node", "name": "speaking", "type": "state"},
            ]
        },
    ).accepted
    # another process claims the person and then dies without releasing
    holder = ros.procs.run(
        "dsr",
        "apply",
        "-",
        input=json.dumps(
            {"claim": [{"node": "person"}]}  # held by a /dsr_cli_<pid> that then exits
        ),
    )
    assert holder.returncode == 0, holder.stdout + holder.stderr
    r = send_and_wait(
        ros,
        agent,
        {"ops": [{"op": "set_node_attrs", "node": "person", "attrs": {"level": 1}}]},
    )
    assert not r.accepted and r.reason["rule"] == "claimed"
    wait_for(
        lambda: len(agent.replica.claims) == 0,
        10,
        "the dead holder's claim to be freed",
        ros.session,
    )
    assert send_and_wait(
        ros,
        agent,
        {"ops": [{"op": "set_node_attrs", "node": "person", "attrs": {"level": 1}}]},
    ).accepted
    # a live holder (this node) is preempted by a higher priority, and told through the delta
    released = []
    agent.add_listener(
        lambda ds, _: released.extend(
            c for d in ds for c in d.get("claims", {}).get("released", [])
        )
    )
    assert send_and_wait(ros, agent, {"claim": [{"from": "person", "to": "speaking"}]}).accepted
    r = ros.procs.run(
        "dsr",
        "apply",
        "-",
        input=json.dumps(
            {"ops": [{"op": "insert_edge", "from": "person", "to": "speaking", "type": "is"}]}
        ),
    )
    assert r.returncode == 0
    wait_for(lambda: released, 10, "the preemption", ros.session)
    assert released[0]["reason"] == "preempted" and released[0]["agent"] == agent.name


def test_two_agents_race_for_one_rule_and_exactly_one_wins(ros):
    start_synced(ros)
    grammar = ros.tmp / "speech.yaml"
    grammar.write_text(
        json.dumps(
            [
                {
                    "name": "start_speaking",
                    "when": [
                        {"edge": ["robot", "speaking", "is_not"]},
                        {
                            "edge": ["test", "test_part", "is_in"],
                            "attrs": {"text": "$text", "sentence_id": "$sid"},
                        },
                    ],
                    "once_per": ["$sid"],
                    "during": [
                        {"delete_edge": ["robot", "speaking", "is_not"]},
                        {"insert_edge": ["robot", "speaking", "is"]},
                    ],
                    "claim": [{"from": "robot", "to": "speaking"}],
                    "priority": 1,
                    "process": "wait",
                    "after": [
                        {"delete_edge": ["robot", "speaking", "is"]},
                        {"insert_edge": ["robot", "speaking", "is_not"]},
                    ],
                }
            ]
        )
    )
    for name in ("speech_a", "speech_b"):
        ros.procs.start(
            name,
            [
                "dsr_rule_agent",
                "--ros-args",
                "-r",
                f"__node:={name}",
                "-p",
                f"grammar_file:={grammar}",
                "-p",
                "process_time:=0.3",
            ],
        )
    agent = agent_in_session(ros)
    deltas = []
    agent.add_listener(lambda ds, _: deltas.extend(ds))
    assert send_and_wait(
        ros,
        agent,
        {
            "ops": [
                {"op": "insert_node", "name": n, "type": t}
                for n, t in [
                    ("robot", "robot"),
                    ("speaking", "state"),
                    ("test", "test"),
                    ("test_part", "test_part"),
                ]
            ]
            + [{"op": "insert_edge", "from": "robot", "to": "speaking", "type": "is_not"}]
        },
    ).accepted
    wait_for(
        lambda: ros.session.node.count_subscribers("dsr/deltas") >= 3,
        20,
        "both rule agents",
        ros.session,
    )
    wait_for(
        lambda: all("running 1 rules" in ros.procs.log(n) for n in ("speech_a", "speech_b")),
        20,
        "both rule agents to be ready",
    )
    for sid in (1, 2, 3):
        assert send_and_wait(
            ros,
            agent,
            {
                "ops": [
                    {
                        "op": "insert_edge" if sid == 1 else "set_edge_attrs",
                        "from": "test",
                        "to": "test_part",
                        "type": "is_in",
                        "attrs": {"text": "Hello", "sentence_id": sid},
                    }
                ]
            },
        ).accepted
        wait_for(
            lambda sid=sid: (
                sum(
                    1
                    for d in deltas
                    if any(
                        o["op"] == "insert_edge" and o["to"] == "speaking" and o["type"] == "is_not"
                        for o in d["ops"]
                    )
                    and d["agent"] != agent.name
                )
                >= sid
            ),
            20,
            f"sentence {sid} to be spoken and finished",
            ros.session,
        )
    starts = [
        d for d in deltas if any(o["op"] == "insert_edge" and o["type"] == "is" for o in d["ops"])
    ]
    assert len(starts) == 3, "exactly one agent took each sentence"
    assert all(
        d["claims"]["granted"][0]["target"] == {"from": "robot", "to": "speaking"} for d in starts
    )
