"""Kinematic chains: values derived by hand, and the algebra T(a,b)T(b,c) = T(a,c),
T(a,b) = T(b,a)^-1 on random trees (hypothesis), against a naive path recomputation."""

import math

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from dsr_graph.model import rigid
from dsr_graph.model.graph import Graph
from dsr_graph.model.transaction import apply_ops


def pose(translation, euler=(0, 0, 0)):
    return {"translation": list(translation), "rotation_euler_xyz": list(euler)}


def test_euler_convention_is_translation_rx_ry_rz():
    # R = Rx(90) Rz(90): e_x -> Rz -> e_y -> Rx -> e_z. The other order (Rz Rx) would give e_y.
    m = rigid.from_translation_euler([1, 2, 3], [math.pi / 2, 0, math.pi / 2])
    assert np.allclose(m[:3, :3] @ [1, 0, 0], [0, 0, 1])
    assert np.allclose(m @ [0, 0, 0, 1], [1, 2, 3, 1])
    # and Ry in the middle: Rx(90) Ry(90) e_z = Rx(90) e_x = e_x
    m = rigid.from_translation_euler([0, 0, 0], [math.pi / 2, math.pi / 2, 0])
    assert np.allclose(m[:3, :3] @ [0, 0, 1], [1, 0, 0])


def test_hand_derived_chain_through_the_common_ancestor():
    g = Graph()
    apply_ops(
        g,
        [
            {"op": "insert_node", "name": "room", "type": "room"},
            {"op": "insert_node", "name": "robot", "type": "robot"},
            {"op": "insert_node", "name": "person", "type": "person"},
            {"op": "insert_node", "name": "camera", "type": "rgbd"},
            # robot at (1000, 0) facing +y (yaw 90 deg); camera 500 up on the robot;
            # person at (1000, 2000)
            {
                "op": "insert_edge",
                "from": "room",
                "to": "robot",
                "type": "RT",
                "rt": pose([1000, 0, 0], [0, 0, math.pi / 2]),
            },
            {
                "op": "insert_edge",
                "from": "robot",
                "to": "camera",
                "type": "RT",
                "rt": pose([0, 0, 500]),
            },
            {
                "op": "insert_edge",
                "from": "room",
                "to": "person",
                "type": "RT",
                "rt": pose([1000, 2000, 0]),
            },
        ],
    )
    assert g.chain("camera", "person") == ["camera", "robot", "room", "person"]
    t = g.transform("camera", "person")
    # Seen from the camera, the person is 2000 straight ahead (+x after the yaw) and 500 below.
    assert np.allclose(t[:3, 3], [2000, 0, -500])
    assert np.allclose(t[:3, :3], [[0, 1, 0], [-1, 0, 0], [0, 0, 1]])  # Rz(-90)
    assert np.allclose(g.transform("person", "camera"), rigid.inverse(t))
    assert np.allclose(g.transform("room", "room"), np.eye(4))


def test_the_cache_follows_moves():
    g = Graph()
    apply_ops(
        g,
        [
            {"op": "insert_node", "name": "room", "type": "room"},
            {"op": "insert_node", "name": "robot", "type": "robot"},
            {"op": "insert_node", "name": "camera", "type": "rgbd"},
            {
                "op": "insert_edge",
                "from": "room",
                "to": "robot",
                "type": "RT",
                "rt": pose([1, 0, 0]),
            },
            {
                "op": "insert_edge",
                "from": "robot",
                "to": "camera",
                "type": "RT",
                "rt": pose([0, 0, 1]),
            },
        ],
    )
    assert np.allclose(g.transform("room", "camera")[:3, 3], [1, 0, 1])
    apply_ops(g, [{"op": "set_rt", "from": "room", "to": "robot", "rt": pose([5, 0, 0])}])
    assert np.allclose(g.transform("room", "camera")[:3, 3], [5, 0, 1])
    # re-parent the camera onto the room in one transaction
    apply_ops(
        g,
        [
            {"op": "delete_edge", "from": "robot", "to": "camera", "type": "RT"},
            {
                "op": "insert_edge",
                "from": "room",
                "to": "camera",
                "type": "RT",
                "rt": pose([0, 7, 0]),
            },
        ],
    )
    assert np.allclose(g.transform("robot", "camera")[:3, 3], [-5, 7, 0])


angle = st.floats(-math.pi, math.pi, allow_nan=False)


@settings(max_examples=300, deadline=None)
@given(a=angle, b=angle, c=angle, lock=st.sampled_from([None, math.pi / 2, -math.pi / 2]))
def test_the_quaternion_is_the_rotation_gimbal_lock_and_half_turns_included(a, b, c, lock):
    """rigid.quaternion_wxyz goes through the Euler angles (cheaper than an eigendecomposition):
    the rotation it gives back is the matrix's, with w >= 0, also where b = +-pi/2."""
    m = rigid.from_translation_euler([0, 0, 0], [a, b if lock is None else lock, c])
    q = rigid.quaternion_wxyz(m)
    assert q[0] >= 0 and math.isclose(sum(v * v for v in q), 1.0, abs_tol=1e-12)
    assert np.allclose(rigid.from_translation_quaternion([0, 0, 0], q), m, atol=1e-12)
    for half_turn in ([math.pi, 0, 0], [0, math.pi, 0], [0, 0, math.pi]):
        m = rigid.from_translation_euler([0, 0, 0], half_turn)
        q = rigid.quaternion_wxyz(m)
        assert np.allclose(rigid.from_translation_quaternion([0, 0, 0], q), m, atol=1e-12)


def test_describe_gives_matrix_translation_and_a_unit_quaternion():
    m = rigid.from_translation_euler([1, 2, 3], [0, 0, math.pi])
    d = rigid.pose_json(m)
    assert d["translation"] == [1.0, 2.0, 3.0]
    w, x, y, z = d["quaternion_wxyz"]
    assert w >= 0 and math.isclose(w * w + x * x + y * y + z * z, 1.0)
    assert np.allclose(rigid.from_translation_quaternion(d["translation"], d["quaternion_wxyz"]), m)


# ------------------------------------------------------------------ properties on random trees
angles = st.floats(-math.pi, math.pi, allow_nan=False)
coords = st.floats(-5000, 5000, allow_nan=False)


@st.composite
def random_tree(draw):
    n = draw(st.integers(2, 12))
    parents = [draw(st.integers(0, i - 1)) for i in range(1, n)]
    poses = [
        pose([draw(coords) for _ in range(3)], [draw(angles) for _ in range(3)])
        for _ in range(1, n)
    ]
    ops = [{"op": "insert_node", "name": f"n{i}", "type": "transform"} for i in range(n)]
    ops += [
        {"op": "insert_edge", "from": f"n{p}", "to": f"n{i + 1}", "type": "RT", "rt": poses[i]}
        for i, p in enumerate(parents)
    ]
    g = Graph()
    apply_ops(g, ops)
    return g, n, parents


def naive(g, parents, a, b):
    """Pose of b in a's frame, multiplying every edge matrix from the root, with general
    inverses."""

    def from_root(i):
        m = np.eye(4)
        path = []
        while i != 0:
            path.append(i)
            i = parents[i - 1]
        for j in reversed(path):
            m = m @ g.edge(f"n{parents[j - 1]}", f"n{j}", "RT").rt
        return m

    return np.linalg.inv(from_root(a)) @ from_root(b)


@settings(max_examples=60, deadline=None)
@given(random_tree(), st.data())
def test_chain_composition_and_inverse(tree, data):
    g, n, parents = tree
    a, b, c = (data.draw(st.integers(0, n - 1)) for _ in range(3))
    tab, tbc, tac = (
        g.transform(f"n{a}", f"n{b}"),
        g.transform(f"n{b}", f"n{c}"),
        g.transform(f"n{a}", f"n{c}"),
    )
    assert np.allclose(tab @ tbc, tac, atol=1e-6)
    assert np.allclose(tab, np.linalg.inv(g.transform(f"n{b}", f"n{a}")), atol=1e-6)
    assert np.allclose(tab, naive(g, parents, a, b), atol=1e-6)
    rigid.check_rigid(tab)


@settings(max_examples=30, deadline=None)
@given(random_tree(), st.data())
def test_chain_passes_through_the_closest_common_ancestor(tree, data):
    g, n, parents = tree
    a, b = data.draw(st.integers(0, n - 1)), data.draw(st.integers(0, n - 1))
    path = g.chain(f"n{a}", f"n{b}")
    assert path[0] == f"n{a}" and path[-1] == f"n{b}"
    assert len(path) == len(set(path)), "a simple path"
    for x, y in zip(
        path, path[1:], strict=False
    ):  # consecutive nodes are joined by an RT edge one way or the other
        assert g.edge(x, y, "RT") is not None or g.edge(y, x, "RT") is not None
