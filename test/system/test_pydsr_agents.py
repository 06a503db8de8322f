"""pydsr agents against a live DSR: two programs written the CORTEX way, in two processes, join one
dsr_server; one writes, the other's signals fire with CORTEX's arguments, and the server, the
listener's replica and the viewer hold the same graph."""

import json
import sys
from pathlib import Path

from browser import free_port, http_get
from ros_processes import snapshot_via, wait_for

REPO = Path(__file__).resolve().parents[2]
WORLD = REPO / "worlds" / "clarc_room.json"
PROGRAMS = Path(__file__).parent / "pydsr_programs"
TOKEN = "a-test-token-of-the-viewer"
WAIT = 60  # seconds for a program on a busy machine


def lines(ros, name):
    return [json.loads(x) for x in ros.procs.log(name).splitlines() if x.startswith("[")]


def viewer_graph(url):
    status, body = http_get(url + "api/graph", TOKEN)
    return json.loads(body) if status == 200 else None


def test_two_pydsr_agents_in_two_processes_share_one_dsr(ros):
    ros.procs.start_server(ros.tmp / "state", world=WORLD)
    snapshot_via(ros.session, timeout=20)
    port = free_port()
    ros.procs.start(
        "viewer", ["dsr_viewer", "--ros-args", "-p", f"port:={port}", "-p", f"token:={TOKEN}"]
    )
    viewer = f"http://127.0.0.1:{port}/"
    done, dumped = ros.tmp / "done", ros.tmp / "listener.json"
    ros.procs.start("listener", [sys.executable, PROGRAMS / "listener.py", done, dumped])
    wait_for(lambda: any(x[0] == "READY" for x in lines(ros, "listener")), WAIT, "the listener")
    _, room, agents_before = next(x for x in lines(ros, "listener") if x[0] == "READY")

    wrote = ros.procs.run(sys.executable, PROGRAMS / "writer.py", timeout=WAIT * 2)
    assert wrote.returncode == 0, wrote.stdout + wrote.stderr
    steps = dict((x[0], x[1]) for x in map(json.loads, wrote.stdout.splitlines()))
    crate, ball = steps["insert_node"], steps["ball"]
    assert all(v for k, v in steps.items() if k != "refused") and steps["refused"] is False, steps
    assert "rt-orphan" in wrote.stderr  # the refusal says why

    expected = [
        ["UPDATE_NODE", crate, "box"],
        ["UPDATE_EDGE", room, crate, "RT"],
        ["UPDATE_NODE_ATTR", crate, ["color"]],
        ["UPDATE_EDGE", crate, room, "in"],
        ["UPDATE_EDGE_ATTR", crate, room, "in", ["color"]],
        ["UPDATE_NODE", ball, "ball"],
        ["UPDATE_NODE_ATTR", ball, ["color"]],  # written by the writer's own handler
        ["UPDATE_EDGE", crate, ball, "RT"],
        ["DELETE_EDGE", crate, room, "in"],
        ["DELETE_EDGE", crate, ball, "RT"],
        ["DELETE_NODE", ball],
        ["DELETE_NODE_OBJ", "ball"],
    ]

    def heard():  # the agents' own info nodes (model/agent_info.py) are not the writer's: those
        # the listener had when it was ready (on a loaded machine the viewer's state changed
        # after that, with no insertion heard) and those inserted since
        signals = [x for x in lines(ros, "listener") if x[0] != "READY"]
        agents = {x[1] for x in signals if x[0] == "UPDATE_NODE" and x[2] == "agent"}
        agents |= set(agents_before)
        return [x for x in signals if x[1] not in agents]

    wait_for(lambda: len(heard()) >= len(expected), WAIT, "the listener's signals")
    assert heard() == expected

    done.touch()
    ros.procs.procs["listener"].wait(timeout=WAIT)
    server = snapshot_via(ros.session, timeout=20)
    wait_for(lambda: (viewer_graph(viewer) or {}).get("seq") == server["seq"], WAIT, "the viewer")
    seen = viewer_graph(viewer)
    replica = json.loads(dumped.read_text())["DSRModel"]["symbols"]

    def shape(doc):
        nodes = {(n["id"], n["name"], n["type"]) for n in doc["nodes"]}
        edges = {(e["from"], e["to"], e["type"]) for e in doc["edges"]}
        return nodes, edges

    names = {int(k): s["name"] for k, s in replica.items()}
    replica_shape = (
        {(int(k), s["name"], s["type"]) for k, s in replica.items()},
        {
            (names[int(link["src"])], names[int(link["dst"])], link["label"])
            for s in replica.values()
            for link in s["links"]
        },
    )
    assert shape(server) == replica_shape == shape(seen)
    crate_node = next(n for n in server["nodes"] if n["name"] == "crate")
    assert (
        crate_node["attrs"]["color"] == "red"
        and replica[str(crate)]["attribute"]["color"]["value"] == "red"
    )
    placed = next(e for e in server["edges"] if e["to"] == "crate")
    assert [row[3] for row in placed["rt"]["matrix"][:3]] == [1.5, 0.5, 0.0]  # metres inside
    link = next(x for x in replica["1"]["links"] if x["dst"] == str(crate))
    assert link["linkAttribute"]["rt_translation"]["value"] == [1500.0, 500.0, 0.0]  # mm outside


def test_the_cortex_style_example_follows_the_robots_barthel_test(ros):
    """examples/cortex_item_audit.py, a pydsr agent, next to the real agents of scripts/launch.sh
    (the default Barthel scenario, in this test's ROS domain): it reports every answered item with
    the answer CGAmed stored, written by /pelea."""
    from ros_processes import EPHEMERAL_PORTS, stored_tests

    db = ros.tmp / "cgamed.sqlite"
    launch = ros.procs.start(
        "launch",
        [
            REPO / "scripts" / "launch.sh",
            *("--scenario", REPO / "scenarios" / "default.yaml", "--db", db),
            *("--timeout", "200", *EPHEMERAL_PORTS, "--run-dir", ros.tmp / "run"),
        ],
    )
    snapshot_via(ros.session, timeout=120)  # the robot's DSR server is up
    ros.procs.start("audit", [sys.executable, REPO / "examples" / "cortex_item_audit.py"])
    assert launch.wait(timeout=260) == 0, ros.procs.log("launch")[-3000:]
    [stored] = stored_tests(db, ros.procs.env())
    answered = {i["item"]: i for i in stored["items"] if i["points"] is not None}

    def answers():
        return {x["item"]: x for x in audit_lines(ros) if x["event"] == "answer"}

    wait_for(lambda: set(answers()) >= set(answered), WAIT, "the audit's answers")
    ros.procs.stop("audit")
    reported = answers()
    assert set(reported) == set(answered), (reported, answered)
    for item, record in reported.items():
        assert (
            record["answer"] == answered[item]["points"] and record["via"] == answered[item]["via"]
        )
        assert record["by"] == "/pelea" and record["at"].endswith("+00:00")
    assert any(x["event"] == "joined" for x in audit_lines(ros))


def audit_lines(ros):
    return [json.loads(x) for x in ros.procs.log("audit").splitlines() if x.startswith("{")]


def test_a_pydsr_agent_reads_the_cameras_images_it_was_not_sent(ros):
    """camera_api on a replica that holds only the images' digests: the writer's
    dsr/get_blob/<node name> brings them (sensor data: the server never had the bytes)."""
    import zlib

    import numpy as np

    from ros_processes import agent_in_session, send_and_wait

    ros.procs.start_server(ros.tmp / "state", world=WORLD)
    snapshot_via(ros.session, timeout=20)
    rgb = np.random.default_rng(1).integers(0, 255, (480, 640, 3), dtype=np.uint8)
    depth = np.random.default_rng(2).random((480, 640), dtype=np.float32)
    agent = agent_in_session(ros)
    image = {"cam_rgb": rgb, "cam_depth": depth, "cam_rgb_width": 640, "cam_rgb_height": 480}
    written = send_and_wait(
        ros, agent, {"ops": [{"op": "set_node_attrs", "node": "kinect", "attrs": image}]}
    )
    assert written.accepted, written.error
    # the writer (this session) answers while the program runs: spun until it ends
    reader = ros.procs.start("camera_reader", [sys.executable, PROGRAMS / "camera_reader.py"])
    ros.session.spin_until(lambda: reader.poll() is not None, WAIT, "camera_reader to end")
    out = ros.procs.log("camera_reader")
    assert reader.returncode == 0, out
    got = json.loads([x for x in out.splitlines() if x.startswith("{")][-1])
    assert got["rgb"] == [[480, 640, 3], "uint8", zlib.crc32(rgb.tobytes())]
    assert got["depth"] == [[480, 640], "float32", zlib.crc32(depth.tobytes())]
    assert got["size"] == [640, 480]
