"""What the DSR server shows ROS 2's own tools, as real processes: each geometric node's pose on
dsr/pose/<node>, the RT tree on /tf and /tf_static, the graph drawn on dsr/markers, a pose at a
past time, and the online verbs taking --ros-args, echo and param as ros2 topic and param do."""

import json
import math
import time
from pathlib import Path

import numpy as np
import pytest
from geometry_msgs.msg import PoseStamped

from dsr_graph.formats.world_files import read_world
from dsr_graph.model import rigid
from dsr_graph.ros.qos import qos_latched

from ros_processes import agent_in_session, send_and_wait, snapshot_via, start_synced, wait_for


def test_pose_topics_match_the_kinematic_chain(ros, cortex_dir):
    start_synced(ros, cortex_dir)
    world = read_world(cortex_dir / "Robot_viriato.json").graph
    poses = {}
    node = ros.session.node
    for name in ("viriato_mesh", "laser1", "viriato_head_camera_tilt_joint"):
        node.create_subscription(
            PoseStamped,
            f"dsr/pose/{name}",
            lambda m, n=name: poses.__setitem__(n, m),
            qos_latched(),
        )
    wait_for(lambda: len(poses) == 3, 15, "three latched poses", ros.session)
    for name, msg in poses.items():
        parent = world.rt_parent(name).name
        assert msg.header.frame_id == parent
        t = world.transform(parent, name)
        p, q = msg.pose.position, msg.pose.orientation
        assert np.allclose([p.x, p.y, p.z], t[:3, 3])
        from dsr_graph.model.rigid import from_translation_quaternion

        assert np.allclose(
            from_translation_quaternion([p.x, p.y, p.z], [q.w, q.x, q.y, q.z]), t, atol=1e-9
        )
    agent = agent_in_session(ros)
    poses.clear()
    send_and_wait(
        ros,
        agent,
        {
            "ops": [
                {
                    "op": "set_rt",
                    "from": "laser_pose",
                    "to": "laser1",
                    "rt": {"translation": [1, 2, 3], "rotation_euler_xyz": [0, 0, math.pi / 2]},
                }
            ]
        },
    )
    wait_for(lambda: "laser1" in poses, 10, "the moved pose", ros.session)
    q = poses["laser1"].pose.orientation
    assert np.allclose([q.w, q.z], [math.cos(math.pi / 4), math.sin(math.pi / 4)])


def test_online_verbs_take_ros_args_like_any_node(ros, cortex_dir):
    """A server in a namespace is reached with -r __ns:=, as `ros2 run` users expect."""
    state = ros.tmp / "state"
    ros.procs.start(
        "server",
        [
            "dsr_server",
            "--ros-args",
            "-r",
            "__ns:=/robot",
            "-p",
            f"state_dir:={state}",
            "-p",
            f"world_file:={cortex_dir / 'Robot_viriato.json'}",
        ],
    )
    r = ros.procs.run("dsr", "get", "robot", "port", "--ros-args", "-r", "__ns:=/robot")
    assert r.returncode == 0 and json.loads(r.stdout)["value"] == 12238, r.stderr
    r = ros.procs.run("dsr", "graph", "--ros-args", "-r", "__ns:=/robot")
    assert r.returncode == 0 and "robot" in r.stdout, r.stderr
    r = ros.procs.run("dsr", "get", "robot", "port", "--timeout", "2")  # not in the namespace
    assert r.returncode == 1 and "no answer" in r.stderr


def test_echo_and_param_do_what_ros2_topic_and_param_would(ros, cortex_dir):
    start_synced(ros, cortex_dir)
    r = ros.procs.run("dsr", "echo", "dsr/heartbeat", "--count", "1", "--field", "seq")
    assert r.returncode == 0 and r.stdout.strip().isdigit(), r.stderr  # latched: heard at once
    r = ros.procs.run("dsr", "echo", "/dsr/heartbeat", "--count", "1", "--field", "nothing")
    assert "(missing: nothing: no 'nothing')" in r.stdout
    r = ros.procs.run("dsr", "param", "list", "dsr_server")
    assert r.returncode == 0 and "agent_grace" in r.stdout.split(), r.stderr
    r = ros.procs.run("dsr", "param", "get", "dsr_server", "agent_grace")
    assert r.returncode == 0 and r.stdout.strip() == "3.0"
    r = ros.procs.run("dsr", "param", "set", "dsr_server", "agent_grace", "5.5")
    assert r.returncode == 0 and r.stdout.strip() == "agent_grace = 5.5", r.stderr
    assert ros.procs.run("dsr", "param", "get", "dsr_server", "agent_grace").stdout.strip() == "5.5"
    r = ros.procs.run("dsr", "param", "set", "dsr_server", "heartbeat_period", "2.0")
    assert r.returncode == 1 and "refused heartbeat_period" in r.stderr and "read-only" in r.stderr
    r = ros.procs.run("dsr", "param", "get", "dsr_server", "no_such")
    assert r.returncode == 1 and "has no parameter no_such" in r.stderr


def test_the_graph_is_drawn_on_dsr_markers_for_rviz(ros, cortex_dir):
    from visualization_msgs.msg import Marker, MarkerArray

    start_synced(ros, cortex_dir)
    arrays = []
    ros.session.node.create_subscription(MarkerArray, "dsr/markers", arrays.append, qos_latched())
    wait_for(lambda: bool(arrays), 15, "a drawing on dsr/markers", ros.session)
    world = read_world(cortex_dir / "Robot_viriato.json").graph
    labels = {m.text for m in arrays[-1].markers if m.ns == "dsr_node_labels"}
    assert labels == {f"{n.name} ({n.type})" for n in world.nodes()}
    assert arrays[-1].markers[0].action == Marker.DELETEALL
    assert {m.header.frame_id for m in arrays[-1].markers[1:]} == {world.rt_root().name}
    agent = agent_in_session(ros)
    send_and_wait(ros, agent, {"ops": [{"op": "insert_node", "name": "cup", "type": "object"}]})
    wait_for(
        lambda: any(m.text == "cup (object)" for m in arrays[-1].markers), 15, "cup", ros.session
    )


def test_the_rt_tree_is_on_tf_static_and_a_moved_edge_on_tf(ros, cortex_dir):
    from rclpy.qos import DurabilityPolicy, QoSProfile
    from tf2_msgs.msg import TFMessage

    start_synced(ros, cortex_dir)
    world = read_world(cortex_dir / "Robot_viriato.json").graph
    statics, dynamics = [], []
    latched = QoSProfile(depth=1, durability=DurabilityPolicy.TRANSIENT_LOCAL)
    node = ros.session.node
    node.create_subscription(TFMessage, "/tf_static", statics.append, latched)
    node.create_subscription(TFMessage, "/tf", dynamics.append, QoSProfile(depth=100))
    wait_for(lambda: bool(statics), 15, "/tf_static", ros.session)
    children = {t.child_frame_id for t in statics[-1].transforms}
    assert children == {world.node(e.dst).name for e in world.edges() if e.type == "RT"}
    laser = next(t for t in statics[-1].transforms if t.child_frame_id == "laser_pose")
    assert laser.header.frame_id == "body" and math.isclose(laser.transform.translation.y, 0.4)
    matrix = world.transform("body", "laser_pose")
    matrix[2, 3] += 0.25  # metres, as everything in the DSR
    agent = agent_in_session(ros)
    rt = rigid.to_json(matrix)
    tx = {"ops": [{"op": "set_rt", "from": "body", "to": "laser_pose", "rt": rt}]}
    assert send_and_wait(ros, agent, tx).accepted
    wait_for(lambda: any(dynamics), 15, "/tf", ros.session)
    moved = dynamics[-1].transforms[0]
    assert moved.child_frame_id == "laser_pose" and math.isclose(
        moved.transform.translation.z, 0.25 + laser.transform.translation.z
    )
    wait_for(
        lambda: "laser_pose" not in {t.child_frame_id for t in statics[-1].transforms},
        15,
        "laser_pose to leave /tf_static",
        ros.session,
    )


def test_a_pose_asked_at_a_past_time_comes_from_the_servers_rt_history(ros):
    """dsr/get_transform through `dsr transform --live --at`: interpolated between the values
    the server stamped, refused by name before what its bounded history holds."""
    world = Path(__file__).resolve().parents[2] / "worlds" / "clarc_room.json"
    ros.procs.start_server(ros.tmp / "state", world=world, rt_history_count=2)
    snapshot_via(ros.session, timeout=20)
    agent = agent_in_session(ros)
    stamps = []
    for x in (1.0, 2.0, 3.0):
        moved = send_and_wait(
            ros,
            agent,
            {
                "ops": [
                    {
                        "op": "set_rt",
                        "from": "room",
                        "to": "chair",
                        "rt": {"translation": [x, 0.0, 0.0], "rotation_euler_xyz": [0, 0, 0]},
                    }
                ]
            },
        )
        assert moved.accepted
        stamps.append(moved.delta["stamp"])
        time.sleep(0.05)  # distinct stamps

    def at(when):
        return ros.procs.run("dsr", "transform", "--live", "room", "chair", "--at", repr(when))

    middle = json.loads(at((stamps[1] + stamps[2]) / 2).stdout)
    assert middle["translation"] == pytest.approx([2.5, 0.0, 0.0])
    now = json.loads(ros.procs.run("dsr", "transform", "--live", "room", "chair").stdout)
    assert now["translation"] == pytest.approx([3.0, 0.0, 0.0])
    refused = at(stamps[0])  # two values kept: the first move is gone
    assert refused.returncode == 1 and "'room'->'chair'" in refused.stderr
    assert "at most 2 values" in refused.stderr
    ago = ros.procs.run("dsr", "transform", "--live", "room", "chair", "--at", "-0.001")
    assert json.loads(ago.stdout)["translation"] == pytest.approx([3.0, 0.0, 0.0])
