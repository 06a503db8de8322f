"""The RT history: each RT edge's recent transforms with the times of the deltas that wrote them,
and a chain asked "at time t": interpolated (translation linearly, rotation by slerp), bounded by
count and age, refused by name outside what is kept; the same on the server and every replica."""

import json

import numpy as np
import pytest

from dsr_graph.exceptions import OutsideHistory
from dsr_graph.model import rigid
from dsr_graph.model.graph import Graph
from dsr_graph.model.rt_history import RtHistory, interpolate
from dsr_graph.protocol.replica import Replica
from dsr_graph.protocol.server_core import Rejection, ServerCore


def pose(x, yaw=0.0):
    return {"translation": [x, 0.0, 0.0], "rotation_euler_xyz": [0.0, 0.0, yaw]}


def tx(*ops):
    return json.dumps({"agent": "/mover", "ops": list(ops)})


def moving_world(times_and_poses, limits=None):
    """room -> cart (loaded, static) -> arm, then the arm moved at the given times."""
    core = ServerCore(Graph())
    setup = core.submit(
        tx(
            {"op": "insert_node", "name": "room", "type": "room"},
            {"op": "insert_node", "name": "cart", "type": "transform"},
            {"op": "insert_node", "name": "arm", "type": "transform"},
            {"op": "insert_edge", "from": "room", "to": "cart", "type": "RT", "rt": pose(1.0)},
            {"op": "insert_edge", "from": "cart", "to": "arm", "type": "RT", "rt": pose(0.0)},
        ),
        now=100.0,
    )
    assert not isinstance(setup, Rejection)
    if limits:
        core.graph.rt_history.limit(*limits)
    deltas = [setup]
    for when, x, yaw in times_and_poses:
        deltas.append(
            core.submit(tx({"op": "set_rt", "from": "cart", "to": "arm", "rt": pose(x, yaw)}), when)
        )
    return core, deltas


def test_between_two_values_a_pose_is_interpolated_translation_and_rotation():
    core, _ = moving_world([(110.0, 2.0, np.pi / 2)])
    at = core.graph.transform_at("cart", "arm", 105.0)
    assert at[:3, 3] == pytest.approx([1.0, 0.0, 0.0])
    assert rigid.euler_xyz(at)[2] == pytest.approx(np.pi / 4)
    assert core.graph.transform_at("cart", "arm", 100.0)[:3, 3] == pytest.approx([0.0, 0, 0])
    # after the newest value, the newest holds; now is the graph as it is
    assert core.graph.transform_at("cart", "arm", 500.0) == pytest.approx(
        core.graph.transform("cart", "arm")
    )
    # a chain through a static edge and a moving one: each edge at that time
    assert core.graph.transform_at("room", "arm", 105.0)[:3, 3] == pytest.approx([2.0, 0, 0])


def test_rotation_takes_the_shortest_arc():
    a = rigid.from_translation_euler([0, 0, 0], [0, 0, np.radians(350)])
    b = rigid.from_translation_euler([0, 0, 0], [0, 0, np.radians(10)])
    mid = interpolate(a, b, 0.5)
    assert mid[:3, :3] == pytest.approx(np.eye(3), abs=1e-9)


def test_a_time_before_an_edge_existed_is_refused_naming_the_edge_and_what_is_held():
    core, _ = moving_world([(110.0, 2.0, 0.0)])
    with pytest.raises(OutsideHistory) as e:
        core.graph.transform_at("room", "arm", 99.0)
    assert "'cart'->'arm'" in str(e.value) and "100.000 to 110.000" in str(e.value)


def test_an_edge_loaded_then_moved_held_its_loaded_value_before():
    core, deltas = moving_world([(110.0, 2.0, 0.0)])
    # a late joiner: the snapshot holds the arm at x=2; then it moves at 120
    late = Replica()
    late.load_snapshot(json.loads(json.dumps(core.snapshot())))
    moved = core.submit(tx({"op": "set_rt", "from": "cart", "to": "arm", "rt": pose(4.0)}), 120.0)
    late.receive(json.loads(json.dumps(moved)))
    assert late.graph.transform_at("cart", "arm", 50.0)[:3, 3] == pytest.approx([2.0, 0, 0])
    assert late.graph.transform_at("cart", "arm", 125.0)[:3, 3] == pytest.approx([4.0, 0, 0])


def test_the_history_is_bounded_by_count_and_by_age_and_refuses_what_it_dropped():
    core, _ = moving_world([(100.0 + i, float(i), 0.0) for i in range(1, 11)], limits=(60.0, 4))
    arm = core.graph.edge("cart", "arm", "RT").key
    assert core.graph.rt_history.span(arm) == (107.0, 110.0)
    assert core.graph.transform_at("cart", "arm", 107.5)[:3, 3] == pytest.approx([7.5, 0, 0])
    with pytest.raises(OutsideHistory, match="at most 4 values"):
        core.graph.transform_at("cart", "arm", 106.0)
    core, _ = moving_world([(100.0 + i, float(i), 0.0) for i in range(1, 11)], limits=(3.5, 100))
    # the value current at the cutoff (110 - 3.5) is kept: 106.5 is still answered
    assert core.graph.rt_history.span(arm) == (106.0, 110.0)
    assert core.graph.transform_at("cart", "arm", 106.5)[:3, 3] == pytest.approx([6.5, 0, 0])


def test_limits_are_checked():
    for age, count in ((0, 10), (-1.0, 10), (1.0, 1), (1.0, 2.5), (True, 10)):
        with pytest.raises(ValueError, match="max_"):
            RtHistory(age, count)


def test_replicas_keep_the_servers_history_and_a_deleted_edge_is_forgotten():
    core, deltas = moving_world([(110.0, 2.0, 0.5), (111.0, 3.0, 0.0)])
    replica = Replica()
    replica.load_snapshot(ServerCore(Graph()).snapshot())
    for delta in deltas:
        replica.receive(json.loads(json.dumps(delta)))
    for when in (100.0, 105.0, 110.5, 200.0):
        assert replica.graph.transform_at("room", "arm", when) == pytest.approx(
            core.graph.transform_at("room", "arm", when)
        )
    key = core.graph.edge("cart", "arm", "RT").key
    core.submit(
        tx(
            {"op": "delete_edge", "from": "cart", "to": "arm", "type": "RT"},
            {"op": "insert_edge", "from": "room", "to": "arm", "type": "RT", "rt": pose(9.0)},
        ),
        130.0,
    )
    assert core.graph.rt_history.span(key) is None  # that edge is gone, and its history


def test_a_clock_that_steps_back_never_reorders_the_history():
    history = RtHistory()
    m = np.eye(4)
    history.record((1, 2, "RT"), 10.0, m)
    history.record((1, 2, "RT"), 9.0, m)
    assert history.span((1, 2, "RT")) == (10.0, 10.0)
