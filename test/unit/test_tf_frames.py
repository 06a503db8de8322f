"""The RT tree as tf2 sees it (protocol/tf_frames.py): frames named after nodes, metres,
quaternions x, y, z, w; composing the /tf_static transforms along the tree gives, for every pair
of geometric nodes of the CLARC room and the CORTEX worlds, what `dsr transform` gives (in
millimetres there); an edge that changes leaves /tf_static for /tf for good."""

import itertools

import numpy as np
import transforms3d

from dsr_graph.formats.world_files import read_world
from dsr_graph.model.vocabulary import RT
from dsr_graph.protocol.tf_frames import TfBook, transform_of

from local_clarc import ROOM


def matrix(t):
    m = np.eye(4)
    x, y, z, w = t.rotation
    m[:3, :3] = transforms3d.quaternions.quat2mat([w, x, y, z])
    m[:3, 3] = t.translation
    return m


def in_root(transforms, root):
    """Each frame's pose in the root frame, composed from parent -> child transforms, as a tf2
    buffer does."""
    by_child = {t.child: t for t in transforms}
    poses = {root: np.eye(4)}

    def pose(frame):
        if frame not in poses:
            t = by_child[frame]
            poses[frame] = pose(t.parent) @ matrix(t)
        return poses[frame]

    for child in by_child:
        pose(child)
    return poses


def agrees_with_the_graph(graph):
    book = TfBook(graph)
    transforms = book.static_transforms(graph)
    assert {t.child for t in transforms} == {
        graph.node(e.dst).name for e in graph.edges() if e.type == RT
    }
    for t in transforms:
        assert np.isclose(np.linalg.norm(t.rotation), 1.0) and t.rotation[3] >= 0
    poses = in_root(transforms, graph.rt_root().name)
    frames = sorted(poses)
    for a, b in itertools.combinations(frames, 2):
        expected = graph.transform(a, b)  # b's pose in a's frame
        got = np.linalg.inv(poses[a]) @ poses[b]
        assert np.allclose(got[:3, :3], expected[:3, :3], atol=1e-9), (a, b)
        assert np.allclose(got[:3, 3], expected[:3, 3], atol=1e-9), (a, b)


def test_tf_agrees_with_dsr_transform_for_every_pair_of_the_clarc_room():
    agrees_with_the_graph(read_world(ROOM).graph)


def test_tf_agrees_with_dsr_transform_for_every_pair_of_the_cortex_worlds(cortex_dir):
    for path in sorted(cortex_dir.glob("*.json")):
        agrees_with_the_graph(read_world(path).graph)


def test_a_changed_edge_leaves_tf_static_for_tf_for_good():
    graph = read_world(ROOM).graph
    book = TfBook(graph)
    leaves = [e for e in graph.edges() if e.type == RT and not graph.rt_children(e.dst)]
    edge = leaves[0]
    parent, child = graph.node(edge.src).name, graph.node(edge.dst).name
    moved = edge.rt.copy()
    moved[:3, 3] += [500.0, 0.0, 0.0]
    graph.set_rt(parent, child, moved)
    now, static_changed = book.update(
        graph, {"ops": [{"op": "set_rt", "from": parent, "to": child}]}
    )
    assert static_changed and [t.child for t in now] == [child]
    assert np.isclose(now[0].translation[0], moved[0, 3])
    assert child not in {t.child for t in book.static_transforms(graph)}
    assert [t.child for t in book.dynamic_transforms(graph)] == [child]
    now, static_changed = book.update(
        graph, {"ops": [{"op": "set_rt", "from": parent, "to": child}]}
    )
    assert not static_changed and len(now) == 1  # already dynamic
    graph.delete_node(child)
    now, static_changed = book.update(graph, {"ops": [{"op": "delete_node", "node": child}]})
    assert now == [] and book.dynamic_transforms(graph) == []
    assert transform_of(graph, child) is None
