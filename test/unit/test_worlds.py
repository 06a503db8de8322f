"""World files: every shared CORTEX world loads or is rejected with a precise reason; transforms
match values derived by hand; both formats round-trip."""

import json
import math

import numpy as np
import pytest

from dsr_graph.exceptions import WorldLoadError
from dsr_graph.formats import cortex
from dsr_graph.formats.world_files import parse_world, read_world, world_document
from dsr_graph.model.binary import dumps, equal

from invariants import assert_invariants

EXPECTED = {  # file -> the violations a careful reader finds in it
    "Robot_giraff.json": ["edge 'mind'->#36451350883598337 (has): node-missing"],
    "Robot_viriato.json": [],
    "autonomyLab_complete.simscene.json": [],
    "autonomyLab_objects.simscene.json": [
        "edge 'fridge'->'fridge' (interactive): no-self-loop",
        "edge 'table'->'table' (interactive): no-self-loop",
    ],
}


@pytest.mark.parametrize("name", sorted(EXPECTED))
def test_every_shared_world_loads_or_names_what_it_rejects(cortex_dir, name):
    world = read_world(cortex_dir / name)
    assert world.format == "cortex"
    reported = [f"{v.element}: {v.rule}" for v in world.violations]
    assert reported == EXPECTED[name]
    assert_invariants(world.graph)
    raw = json.loads((cortex_dir / name).read_text())["DSRModel"]["symbols"]
    assert len(world.graph) == len(raw)  # every node survived


def test_viriato_transforms_by_hand(cortex_dir):
    g = read_world(cortex_dir / "Robot_viriato.json").graph
    # CORTEX's millimetres are metres in the DSR (_translation takes mm)
    # robot -> body (0) -> laser_pose (0, 400, 0) -> laser1 (100, 0, 100): translations add up
    assert np.allclose(g.transform("robot", "laser1"), _translation(100, 400, 100))
    # laser2 seen from laser1: (-100, 0, -100) - (100, 0, 100)
    assert np.allclose(g.transform("laser1", "laser2"), _translation(-200, 0, -200))
    # viriato_mesh sits 200 up on the body, yawed by th: laser_pose (0, 400, 0) seen from the mesh
    # is R_z(-th) (0, 400, -200) = (400 sin th, 400 cos th, -200)
    th = 1.5700000524520874
    t = g.transform("viriato_mesh", "laser_pose")
    assert np.allclose(t[:3, 3] * 1000, [400 * math.sin(th), 400 * math.cos(th), -200])
    # pan joint yaws by a, tilt joint pitches by b about x: R = Rz(a) Rx(b), so e_y maps to
    # (-sin a cos b, cos a cos b, sin b)
    a, b = -0.0005755375605076551, 0.0011809815187007189
    r = g.transform("viriato_head_camera_pan_tilt", "viriato_head_camera_tilt_joint")[:3, :3]
    assert np.allclose(
        r @ [0, 1, 0], [-math.sin(a) * math.cos(b), math.cos(a) * math.cos(b), math.sin(b)]
    )
    # the camera sensor, four frames down the head, in the base laser's frame: only translations
    # (57, 1368 up the body) and the tiny head rotations, which move nothing at the origin
    t = g.transform("laser", "viriato_head_camera_sensor")
    assert np.allclose(t[:3, 3] * 1000, [0, 57 - 400, 1368])


def test_autonomy_lab_transform_with_a_real_rotation(cortex_dir):
    g = read_world(cortex_dir / "autonomyLab_complete.simscene.json").graph
    raw = json.loads((cortex_dir / "autonomyLab_complete.simscene.json").read_text())["DSRModel"][
        "symbols"
    ]
    link = next(k for k in raw["1"]["links"] if k["dst"] == 2)
    (tx, ty, tz) = link["linkAttribute"]["rt_translation"]["value"]
    (ax, ay, az) = link["linkAttribute"]["rt_rotation_euler_xyz"]["value"]
    child = raw["2"]["name"]
    t = g.transform("world", child)
    assert np.allclose(t[:3, 3] * 1000, [tx, ty, tz])  # CORTEX's mm, the DSR's metres
    # ax, ay are ~1e-7: the rotation is a yaw by az to within 1e-6
    assert np.allclose(t[:3, :3] @ [1, 0, 0], [math.cos(az), math.sin(az), 0], atol=1e-6)
    back = g.transform(child, "world")
    assert np.allclose(back @ t, np.eye(4))


def same_attrs(a, b) -> bool:
    """Attributes alike, binary values (a camera's images) element by element."""
    return a.keys() == b.keys() and all(equal(a[k], b[k]) for k in a)


@pytest.mark.parametrize("name", sorted(EXPECTED))
def test_round_trip_through_both_formats(cortex_dir, name):
    original = read_world(cortex_dir / name).graph
    ours = parse_world(json.loads(dumps(world_document(original, "dsr"))))
    assert ours.violations == [] and ours.format == "dsr"
    theirs = parse_world(json.loads(dumps(world_document(ours.graph, "cortex"))))
    assert theirs.violations == [] and theirs.format == "cortex"
    for g in (ours.graph, theirs.graph):
        assert sorted((n.id, n.name, n.type) for n in g.nodes()) == sorted(
            (n.id, n.name, n.type) for n in original.nodes()
        )
        for n in original.nodes():
            assert same_attrs(g.node(n.name).attrs, n.attrs), n.name
        for e in original.edges():
            copy = g.edge(e.src, e.dst, e.type)
            assert copy is not None and same_attrs(copy.attrs, e.attrs)
            if e.rt is not None:
                assert np.allclose(copy.rt, e.rt, atol=1e-9)


def test_cortex_uint64_is_written_back_as_a_string(cortex_dir):
    g = read_world(cortex_dir / "Robot_viriato.json").graph
    doc = cortex.to_cortex(g)
    assert doc["DSRModel"]["symbols"]["1000"]["attribute"]["parent"] == {"type": 7, "value": "200"}


@pytest.mark.parametrize(
    "doc, fragment",
    [
        ({"nodes": []}, "not a world file"),
        ({"format": "dsr-graph", "version": 9, "kind": "world"}, "unsupported version 9"),
        ({"format": "dsr-graph", "version": 1, "kind": "movie"}, '"kind"'),
        ({"DSRModel": {"symbols": []}}, "symbols must be an object"),
    ],
)
def test_unreadable_documents_say_why(doc, fragment):
    with pytest.raises(WorldLoadError, match=fragment):
        parse_world(doc)


def test_our_world_format_reports_each_bad_element():
    doc = {
        "format": "dsr-graph",
        "version": 1,
        "kind": "world",
        "nodes": [
            {"name": "room", "type": "room"},
            {"name": "x", "type": "spaceship"},
            {"name": "robot", "type": "robot", "attrs": {"level": "high", "pos_x": 1}},
            {"type": "robot"},
        ],
        "edges": [
            {
                "from": "room",
                "to": "robot",
                "type": "RT",
                "rt": {"translation": [0, 0, 0], "rotation_euler_xyz": [0, 0, 0]},
            },
            {"from": "robot", "to": "room", "type": "RT", "rt": {"matrix": np.eye(4).tolist()}},
            {"from": "room", "to": "x", "type": "has"},
        ],
    }
    world = parse_world(doc, source="w.json")
    lines = [str(v) for v in world.violations]
    assert lines == [
        "w.json: nodes[1]: node 'x': unknown-node-type: node type 'spaceship' is not in the "
        "vocabulary (extend it to add one)",
        "w.json: nodes[2]: node 'robot': attribute-type: attribute 'level' must be int: "
        "expected an integer, got str 'high'",
        'w.json: nodes[3]: nodes[3]: malformed: a node needs "name" and "type"',
        "w.json: edges[1]: edge 'robot'->'room' (RT): rt-acyclic: 'room' is an RT ancestor of "
        "'robot': this edge would close a cycle",
        "w.json: edges[2]: edge 'room'->'x' (has): node-missing: node 'x' does not exist",
    ]
    assert world.graph.node("robot").attrs == {"pos_x": 1.0}  # the good attribute stays


def _translation(x, y, z):
    """A pure translation given in millimetres, as the DSR holds it (metres)."""
    m = np.eye(4)
    m[:3, 3] = [x / 1000, y / 1000, z / 1000]
    return m
