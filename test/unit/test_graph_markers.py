"""The graph drawn for RViz and Foxglove (protocol/graph_markers.py): every node and edge of the
CLARC room and of the CORTEX worlds, geometric nodes at their kinematic pose in metres, symbols
above what they are linked to, and the drawing follows the graph as it changes."""

import numpy as np
import pytest

from dsr_graph.formats.world_files import read_world
from dsr_graph.model.vocabulary import RT
from dsr_graph.protocol.graph_markers import ROW_GAP, SYMBOL_RISE, drawing

from local_clarc import ROOM


def check(graph):
    d = drawing(graph)
    root = graph.rt_root().name
    assert d.frame == root
    assert [n.name for n in d.nodes] == sorted(n.name for n in graph.nodes())
    assert len(d.edges) == sum(1 for _ in graph.edges())
    where = {n.name: n for n in d.nodes}
    for node in d.nodes:
        if node.geometric and node.name != root:
            expected = graph.transform(root, node.name)[:3, 3]
            assert np.allclose(node.position, expected), node.name
        assert node.geometric == (graph.is_geometric(node.name) or node.name == root)
    for edge in d.edges:
        assert edge.start == where[edge.src].position and edge.end == where[edge.dst].position
    return d


def test_the_clarc_room_is_drawn_in_metres_with_symbols_above_their_anchor():
    graph = read_world(ROOM).graph
    d = check(graph)
    where = {n.name: n for n in d.nodes}
    for node in d.nodes:
        if node.geometric:
            continue
        anchors = [
            where[graph.node(e.dst if graph.node(e.src).name == node.name else e.src).name]
            for e in graph.edges()
            if e.type != RT and node.name in (graph.node(e.src).name, graph.node(e.dst).name)
        ]
        anchors = [a for a in anchors if a.geometric]
        if anchors:  # above its alphabetically first geometric neighbour, by whole rises
            anchor = min(anchors, key=lambda a: a.name)
            rise = (node.position[2] - anchor.position[2]) / SYMBOL_RISE
            assert node.position[:2] == anchor.position[:2] and rise == round(rise) >= 1
        else:  # in the row above the scene
            top = max(n.position[2] for n in d.nodes if n.geometric)
            assert node.position[2] >= top + ROW_GAP - 1e-9


def test_the_cortex_worlds_are_drawn_whole(cortex_worlds):
    for path in cortex_worlds:
        check(read_world(path).graph)


def test_a_change_moves_the_drawing():
    graph = read_world(ROOM).graph
    before = {n.name: n.position for n in drawing(graph).nodes}
    moved = [e for e in graph.edges() if e.type == RT][0]
    child = graph.node(moved.dst).name
    matrix = moved.rt.copy()
    matrix[:3, 3] += [1.0, 0.0, 0.0]  # one metre along x in the parent's frame
    graph.set_rt(graph.node(moved.src).name, child, matrix)
    after = {n.name: n.position for n in drawing(graph).nodes}
    assert after[child] != before[child]
    assert np.isclose(np.linalg.norm(np.subtract(after[child], before[child])), 1.0)


@pytest.fixture
def cortex_worlds(cortex_dir):
    return sorted(cortex_dir.glob("*.json"))
