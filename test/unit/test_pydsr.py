"""pydsr, CORTEX's Python API, on a graph of the process's own (a world file): the calls of
CORTEX's python-wrapper/index.md and python_api.cpp, as CORTEX's own tests use them, the
millimetres at the boundary, refusals, and the signals."""

import json
import logging

import numpy as np
import pytest

from pydsr import Attribute, DSRGraph, Edge, Node, camera_api, inner_api, rt_api, signals

# a CORTEX world (its format: mm, ids as strings), root -> robot -> laser, root -> table
WORLD = {
    "DSRModel": {
        "symbols": {
            "1": {
                "id": "1",
                "name": "root",
                "type": "root",
                "attribute": {"color": {"type": 0, "value": "SeaGreen"}},
                "links": [
                    {
                        "src": "1",
                        "dst": "2",
                        "label": "RT",
                        "linkAttribute": {
                            "rt_translation": {"type": 3, "value": [1000.0, 2000.0, 0.0]},
                            "rt_rotation_euler_xyz": {"type": 3, "value": [0.0, 0.0, 1.5707963]},
                        },
                    },
                    {
                        "src": "1",
                        "dst": "4",
                        "label": "RT",
                        "linkAttribute": {
                            "rt_translation": {"type": 3, "value": [-500.0, 0.0, 0.0]},
                            "rt_rotation_euler_xyz": {"type": 3, "value": [0.0, 0.0, 0.0]},
                        },
                    },
                ],
            },
            "2": {
                "id": "2",
                "name": "robot",
                "type": "omnirobot",
                "attribute": {"pos_x": {"type": 2, "value": 10.5}},
                "links": [
                    {
                        "src": "2",
                        "dst": "3",
                        "label": "RT",
                        "linkAttribute": {
                            "rt_translation": {"type": 3, "value": [100.0, 0.0, 300.0]},
                            "rt_rotation_euler_xyz": {"type": 3, "value": [0.0, 0.0, 0.0]},
                        },
                    }
                ],
            },
            "3": {"id": "3", "name": "laser", "type": "laser", "attribute": {}, "links": []},
            "4": {"id": "4", "name": "table", "type": "table", "attribute": {}, "links": []},
        }
    }
}


@pytest.fixture
def world(tmp_path):
    path = tmp_path / "world.json"
    path.write_text(json.dumps(WORLD))
    return str(path)


@pytest.fixture
def g(world):
    graph = DSRGraph(0, "tester", 12, world, True)
    yield graph
    graph.close()


# -- Attribute, Edge, Node (detached) -----------------------------------------------------------
def test_an_attribute_keeps_its_kind_of_value_and_its_stamps_are_read_only():
    a = Attribute(10.4, 0, 12)
    assert a.value == pytest.approx(10.4) and a.timestamp == 0 and a.agent_id == 12
    with pytest.raises(TypeError, match="cannot change type"):
        a.value = True
    with pytest.raises(TypeError):
        a.value = "ten"
    a.value = 0.0
    assert a.value == 0.0 and a.timestamp > 0  # a new value is stamped now
    with pytest.raises(AttributeError):
        a.agent_id = 100
    with pytest.raises(AttributeError):
        a.timestamp = 100
    b = Attribute(10.4, 7)  # (value, agent_id): stamped now
    assert b.agent_id == 7 and b.timestamp > 0
    v = Attribute([1.0, 2.0, 3.0], 0, 1)
    assert v.value.dtype == np.float32 and list(v.value) == [1.0, 2.0, 3.0]
    with pytest.raises(TypeError):
        v.value = 3.0


def test_an_edge_is_made_destination_first_and_its_ends_are_read_only():
    e = Edge(10, 11, "RT", 0)
    assert (e.destination, e.origin, e.type, e.agent_id) == (10, 11, "RT", 0)
    for name in ("type", "origin", "destination"):
        with pytest.raises(AttributeError):
            setattr(e, name, 22)
    e.agent_id = 22
    by_name = Edge(to=10, **{"from": 11}, type="RT", agent_id=3)  # CORTEX's keywords
    assert (by_name.destination, by_name.origin, by_name.agent_id) == (10, 11, 3)
    with pytest.raises(TypeError):
        Edge(10, 11)
    e.attrs["test"] = Attribute(10.4, 0, 12)
    assert len(e.attrs) == 1
    del e.attrs["test"]
    with pytest.raises(KeyError):
        e.attrs["test"]


def test_a_node_type_outside_cortex_registry_is_a_runtime_error():
    n = Node(1, "root", "name")
    assert (n.name, n.type, n.agent_id, n.id) == ("name", "root", 1, 0)
    with pytest.raises(RuntimeError):
        Node(1, "test")
    with pytest.raises(AttributeError):
        n.name = "newname"
    n.edges[(11, "RT")] = Edge(11, 1, "RT", 0)
    assert len(n.edges) == 1 and len(n.get_edges()) == 1


# -- DSRGraph ------------------------------------------------------------------------------------
def test_reads_by_id_and_by_name(g):
    assert g.get_node(1).name == "root" and g.get_node("root").id == 1
    assert g.get_node(1000000) is None and g.get_node("weirdname") is None
    assert g.get_node_root().name == "root"
    assert [n.name for n in g.get_nodes_by_type("laser")] == ["laser"]
    assert g.get_nodes_by_type("invalidtype") == [] and len(g.get_nodes()) == 4
    assert g.get_name_from_id(2) == "robot" and g.get_name_from_id(999) is None
    assert g.get_id_from_name("laser") == 3 and g.get_id_from_name("nobody") is None
    assert g.get_edge(1, 2, "RT") is not None and g.get_edge("root", "robot", "RT") is not None
    assert g.get_edge(11111, 22222, "RT") is None and g.get_edge("a", "b", "RT") is None
    assert len(g.get_edges_by_type("RT")) == 3 and g.get_edges_by_type("in") == []
    assert sorted((e.origin, e.destination) for e in g.get_edges()) == [(1, 2), (1, 4), (2, 3)]
    assert [e.origin for e in g.get_edges_to_id(3)] == [2] and g.get_edges_to_id(1) == []
    root = g.get_node("root")
    assert set(root.edges) == {(2, "RT"), (4, "RT")}
    assert g.get_agent_id() == 12 and g.get_agent_name() == "tester"


def test_rt_translations_are_millimetres_at_the_boundary_and_metres_inside(g):
    edge = g.get_edge(1, 2, "RT")
    assert list(edge.attrs["rt_translation"].value) == pytest.approx([1000.0, 2000.0, 0.0])
    assert edge.attrs["rt_translation"].value.dtype == np.float32
    assert g._graph.edge(1, 2, "RT").rt[:3, 3] == pytest.approx([1.0, 2.0, 0.0])
    rt = rt_api(g)
    assert rt.insert_or_assign_edge_RT(g.get_node("robot"), 3, [250.0, 0.0, 0.0], [0.0, 0.0, 0.0])
    assert g._graph.edge(2, 3, "RT").rt[:3, 3] == pytest.approx([0.25, 0.0, 0.0])
    assert rt.get_translation(2, 3) == pytest.approx([250.0, 0.0, 0.0])


def test_update_node_writes_what_changed_and_removes_what_was_dropped(g):
    root = g.get_node("root")
    root.attrs["color"].value = "red"
    assert g.update_node(root) is True
    assert g.get_node("root").attrs["color"].value == "red"
    robot = g.get_node("robot")
    del robot.attrs["pos_x"]
    assert g.update_node(robot) and "pos_x" not in g.get_node("robot").attrs
    ghost = Node._of(99, "mesh", "ghost")
    assert g.update_node(ghost) is False


def test_insert_node_returns_the_id_and_names_an_unnamed_node_as_cortex_does(g):
    new = g.insert_node(Node(12, "mesh", "newmesh"))
    assert new is not None and g.get_node("newmesh").id == new
    assert g.insert_node(Node(12, "mesh", "newmesh")) is None  # the name exists
    unnamed = g.insert_node(Node(12, "mesh"))
    assert g.get_node(unnamed).name == f"mesh_{unnamed}"
    with_edge = Node(12, "box", "crate")
    with_edge.edges[(4, "in")] = Edge(4, 0, "in", 12)
    crate = g.insert_node(with_edge)
    assert g.get_edge(crate, 4, "in") is not None


def test_edges_are_inserted_assigned_and_deleted(g):
    edge = g.get_edge(1, 2, "RT")
    edge.attrs["color"] = Attribute("red")
    assert edge.attrs["color"].agent_id == 12  # the graph's agent, as CORTEX stamps it
    assert g.insert_or_assign_edge(edge)
    assert g.get_edge(1, 2, "RT").attrs["color"].value == "red"
    assert g._graph.edge(1, 2, "RT").rt[:3, 3] == pytest.approx([1.0, 2.0, 0.0])  # unchanged
    assert g.insert_or_assign_edge(Edge(1, 2, "in", 12)) and g.get_edge(2, 1, "in") is not None
    assert g.insert_or_assign_edge(Edge(1, 777, "in", 12)) is False  # no node 777
    assert g.delete_edge(2, 1, "in") is True and g.get_edge(2, 1, "in") is None
    assert g.delete_edge(111111, 22222, "RT") is False


def test_an_rt_edge_to_a_node_with_a_parent_moves_it(g):
    rt = rt_api(g)
    assert rt.insert_or_assign_edge_RT(g.get_node("table"), 3, [0.0, 0.0, 800.0], [0.0, 0.0, 0.0])
    assert g.get_edge(2, 3, "RT") is None and g.get_edge(4, 3, "RT") is not None
    assert g._graph.rt_parent(3).name == "table"


def test_a_refused_write_returns_false_changes_nothing_and_says_why(g, caplog):
    before = len(g.get_nodes())
    with caplog.at_level(logging.WARNING, logger="pydsr"):
        assert g.delete_node("robot") is False  # it has an RT child: the DSR keeps poses
    assert "rt-orphan" in caplog.text and len(g.get_nodes()) == before
    assert g.delete_node("nobody") is False
    assert g.delete_node("laser") is True and g.get_node("laser") is None
    assert g.get_edge(2, 3, "RT") is None


def test_each_graph_from_a_file_is_fresh(world):
    first = DSRGraph(0, "one", 1, world)
    first.delete_node("table")
    second = DSRGraph(0, "two", 2, world)
    assert first.get_node("table") is None and second.get_node("table") is not None


def test_rt_api_reads_poses_in_millimetres(g):
    rt = rt_api(g)
    edge = rt.get_edge_RT(g.get_node("root"), 2)
    assert edge.type == "RT" and rt.get_edge_RT(g.get_node("root"), 3) is None
    m = rt.get_edge_RT_as_rtmat(edge)
    assert m[:3, 3] == pytest.approx([1000.0, 2000.0, 0.0])
    assert m[:3, :3] @ [1, 0, 0] == pytest.approx([0, 1, 0], abs=1e-6)
    pose = rt.get_RT_pose_from_parent(g.get_node("laser"))
    assert pose[:3, 3] == pytest.approx([100.0, 0.0, 300.0])
    assert rt.get_RT_pose_from_parent(g.get_node("root")) is None


def test_cortex_timestamps_ask_the_rt_history_in_nanoseconds(g):
    import time

    rt, inner = rt_api(g), inner_api(g)
    loaded = time.time_ns()
    assert rt.insert_or_assign_edge_RT(g.get_node("robot"), 3, [300.0, 0.0, 300.0], [0, 0, 0])
    moved = time.time_ns()
    assert rt.insert_or_assign_edge_RT(g.get_node("robot"), 3, [500.0, 0.0, 300.0], [0, 0, 0])
    # before the first move, the laser held what the file said; then the history has it
    assert rt.get_translation(2, 3, loaded - 10**9) == pytest.approx([100.0, 0.0, 300.0])
    assert rt.get_translation(2, 3, time.time_ns())[0] == pytest.approx(500.0)
    between = rt.get_translation(2, 3, moved)[0]
    assert 300.0 <= between <= 500.0
    edge = rt.get_edge_RT(g.get_node("robot"), 3)
    assert rt.get_edge_RT_as_rtmat(edge, loaded - 10**9)[:3, 3] == pytest.approx([100, 0, 300])
    assert inner.transform("root", "laser", loaded - 10**9) == pytest.approx(
        [1000.0, 2100.0, 300.0], abs=1e-3
    )
    # an edge made here did not exist before: that time is refused (None, the reason logged)
    box = g.insert_node(Node(12, "box", "box"))
    made = time.time_ns()
    rt.insert_or_assign_edge_RT(g.get_node("root"), box, [0.0, 0.0, 0.0], [0, 0, 0])
    assert rt.get_translation(1, box, made - 10**9) is None
    assert inner.transform("root", "box", made - 10**9) is None


def test_inner_api_transforms_between_frames_in_millimetres(g):
    inner = inner_api(g)
    # the laser: 100 mm ahead of the robot, which faces +y at (1000, 2000): (1000, 2100, 300)
    assert inner.transform("root", "laser") == pytest.approx([1000.0, 2100.0, 300.0], abs=1e-3)
    assert inner.transform("root", [10.0, 0.0, 0.0], "laser", 0) == pytest.approx(
        [1000.0, 2110.0, 300.0], abs=1e-3
    )
    assert inner.transform("laser", "root") == pytest.approx([-2100.0, 1000.0, -300.0], abs=1e-3)
    axis = inner.transform_axis("root", "laser", 0)
    assert axis[:3] == pytest.approx([1000.0, 2100.0, 300.0], abs=1e-3)
    assert axis[5] == pytest.approx(1.5707963, abs=1e-6)
    assert inner.transform_axis("root", [0, 0, 0, 0, 0, 0.1], "laser")[5] == pytest.approx(
        1.6707963, abs=1e-6
    )
    m = inner.get_transformation_matrix("root", "laser")
    assert m.shape == (4, 4) and m[:3, 3] == pytest.approx([1000.0, 2100.0, 300.0], abs=1e-3)
    assert inner.get_translation_vector("root", "table") == pytest.approx([-500.0, 0.0, 0.0])
    assert inner.get_rotation_matrix("root", "laser") @ [1, 0, 0] == pytest.approx(
        [0, 1, 0], abs=1e-6
    )
    assert inner.get_euler_xyz_angles("root", "laser")[2] == pytest.approx(1.5707963, abs=1e-6)
    assert inner.transform("root", "nobody") is None


def test_write_to_json_file_is_cortex_format_without_the_skipped_attributes(g, tmp_path):
    out = tmp_path / "out.json"
    g.write_to_json_file(str(out), ["color"])
    symbols = json.loads(out.read_text())["DSRModel"]["symbols"]
    assert "color" not in symbols["1"]["attribute"] and symbols["2"]["attribute"]["pos_x"]
    link = next(x for x in symbols["1"]["links"] if x["dst"] == "2")
    assert link["linkAttribute"]["rt_translation"]["value"] == pytest.approx([1000, 2000, 0])
    again = DSRGraph(0, "reader", 3, str(out))
    assert len(again.get_nodes()) == 4


# -- signals ---------------------------------------------------------------------------------
def test_every_change_fires_cortex_signals_with_cortex_arguments(g):
    heard = []
    for kind in (
        signals.UPDATE_NODE,
        signals.UPDATE_NODE_ATTR,
        signals.UPDATE_EDGE,
        signals.UPDATE_EDGE_ATTR,
        signals.DELETE_EDGE,
        signals.DELETE_NODE,
        signals.DELETE_NODE_OBJ,
        signals.DELETE_EDGE_OBJ,
    ):
        signals.connect(g, kind, lambda *args, kind=kind: heard.append((kind.name, *args)))
    new = g.insert_node(Node(12, "mesh", "m"))
    assert heard == [("UPDATE_NODE", new, "mesh")]
    heard.clear()
    node = g.get_node("robot")
    node.attrs["pos_x"].value = 11.0
    g.update_node(node)
    assert heard == [("UPDATE_NODE_ATTR", 2, ["pos_x"])]
    heard.clear()
    g.insert_or_assign_edge(Edge(4, new, "in", 12))
    edge = g.get_edge(new, 4, "in")
    edge.attrs["color"] = Attribute("blue")
    g.insert_or_assign_edge(edge)
    rt_api(g).insert_or_assign_edge_RT(g.get_node("root"), 3, [0, 0, 0], [0, 0, 0])
    assert heard[0] == ("UPDATE_EDGE", new, 4, "in")
    assert heard[1] == ("UPDATE_EDGE_ATTR", new, 4, "in", ["color"])
    assert ("DELETE_EDGE", 2, 3, "RT") in heard and heard[-1] == ("UPDATE_EDGE", 1, 3, "RT")
    heard.clear()
    g.delete_node(new)
    kinds = [h[0] for h in heard]
    assert kinds == ["DELETE_EDGE", "DELETE_EDGE_OBJ", "DELETE_NODE", "DELETE_NODE_OBJ"]
    assert heard[0] == ("DELETE_EDGE", new, 4, "in") and heard[2] == ("DELETE_NODE", new)
    assert heard[3][1].name == "m" and heard[1][1].destination == 4


def test_a_handler_may_write_and_a_failing_handler_stops_nothing(g, caplog):
    heard = []

    def mark(id, type):
        if type == "mesh":  # writes from inside a handler: its own signal comes after
            node = g.get_node(id)
            node.attrs["color"] = Attribute("seen")
            g.update_node(node)

    def broken(id, names):
        raise ValueError("a bug in a handler")

    signals.connect(g, signals.UPDATE_NODE, mark)
    signals.connect(g, signals.UPDATE_NODE_ATTR, broken)
    signals.connect(g, signals.UPDATE_NODE_ATTR, lambda id, names: heard.append((id, names)))
    with caplog.at_level(logging.ERROR, logger="pydsr"):
        new = g.insert_node(Node(12, "mesh", "m"))
    assert g.get_node(new).attrs["color"].value == "seen"
    assert heard == [(new, ["color"])] and "a bug in a handler" in caplog.text
    with pytest.raises(TypeError):
        signals.connect(g, signals.UPDATE_NODE, "not a function")


def test_cortex_own_world_file_loads_and_answers(cortex_dir):
    g = DSRGraph(0, "Prueba", 12, str(cortex_dir / "autonomyLab_objects.simscene.json"), True)
    assert len(g.get_nodes()) == 41 and len(g.get_nodes_by_type("rgbd")) == 1
    assert g.get_node_root().name == "world"
    inner = inner_api(g)
    assert inner.transform("world", "laser", 0) is not None
    assert inner.transform("world", [1.1, 3.3, 6.6], "laser", 0) is not None
    assert rt_api(g).get_translation(1, 2, 0) is not None


def test_an_attribute_read_from_the_graph_says_who_wrote_it_and_when(g):
    import time

    from pydsr.elements import agent_number

    before = time.time_ns()
    root = g.get_node("root")
    root.attrs["color"].value = "red"
    g.update_node(root)
    color = g.get_node("root").attrs["color"]
    assert color.agent_name == "/tester" and color.agent_id == agent_number("/tester")
    assert before - 1e6 <= color.timestamp <= time.time_ns() + 1e6
    loaded = g.get_node("robot").attrs["pos_x"]  # from the file: nobody wrote it here
    assert (loaded.timestamp, loaded.agent_id, loaded.agent_name) == (0, 0, "")
    rt_api(g).insert_or_assign_edge_RT(g.get_node("robot"), 3, [1.0, 2.0, 3.0], [0, 0, 0])
    moved = g.get_edge(2, 3, "RT").attrs["rt_translation"]
    assert moved.agent_name == "/tester" and moved.timestamp >= before
    assert agent_number("/tester") == agent_number("/tester") != agent_number("/speech")


def test_camera_api_reads_a_camera_nodes_images(tmp_path):
    import base64

    rgb = np.arange(4 * 6 * 3, dtype=np.uint8).reshape(4, 6, 3)
    depth = np.linspace(0.5, 4.0, 24, dtype=np.float32).reshape(4, 6)
    world = {
        "format": "dsr-graph",
        "version": 1,
        "kind": "world",
        "units": {"length": "m"},
        "nodes": [
            {"name": "room", "type": "room"},
            {
                "name": "kinect",
                "type": "rgbd",
                "attrs": {
                    "cam_rgb_width": 6,
                    "cam_rgb_height": 4,
                    "cam_rgb": {
                        "$array": base64.b64encode(rgb.tobytes()).decode(),
                        "dtype": "uint8",
                        "shape": [4, 6, 3],
                    },
                    "cam_depth": {
                        "$array": base64.b64encode(depth.tobytes()).decode(),
                        "dtype": "float32",
                        "shape": [4, 6],
                    },
                },
            },
            {"name": "panel", "type": "panel"},
        ],
        "edges": [
            {"from": "room", "to": "kinect", "type": "RT", "rt": {"matrix": np.eye(4).tolist()}}
        ],
    }
    path = tmp_path / "camera.json"
    path.write_text(json.dumps(world))
    g = DSRGraph(0, "viewer", 5, str(path))
    camera = camera_api(g, g.get_node("kinect"))
    assert np.array_equal(camera.get_rgb_image(), rgb) and camera.get_rgb_image().dtype == np.uint8
    assert np.array_equal(camera.get_depth_image(), depth)
    assert (camera.width, camera.height, camera.id) == (6, 4, g.get_id_from_name("kinect"))
    assert camera_api(g, g.get_node("panel")).get_rgb_image() is None


F = np.float64  # CORTEX's tests say np.float, which numpy no longer has


@pytest.mark.parametrize(
    "name, good, bad_attributes, bad_values",
    [
        (
            "vehicle_id",
            [10, 11, int(12.45)],
            [10.0, "10.0", True, [10], [10.0], [10, 12]],
            ["s", 10.0, [10], (10,), np.array([1.2], F)],
        ),
        (
            "vehicle_occupancy",
            [True, False],
            [10.0, "10.0", 1, 0, [10], [10.0]],
            [1, 1.0, "True", [True]],
        ),
        (
            "vehicle_steer",
            [1.0, float(12)],
            [True, "10.0", 1, 0, [10], [10.0, 11.2]],
            [1, "1.0", [1.0], np.array([1.2], F)],
        ),
        (
            "test_double_type",
            [1.0, 1.1324325435436457],
            [True, "10.0", 1, -12, [10.0]],
            [1, "1.0", -12, True, [10.0]],
        ),
        (
            "name",
            ["Prueba"],
            [True, 10.0, 1, [10], [10.0, 11.2]],
            [1, np.array([1.2], F), [10.0], True],
        ),
        (
            "rt_translation",
            [[10.0], [10.0, 11.2], np.array([1.2, 4.4], F)],
            [
                True,
                10.0,
                1,
                [10],
                "[10.0]",
                [10, 12, 22],
                np.array([12, 44], np.uint8),
                np.array([12, 44], np.uint64),
            ],
            [[10, 11], np.array([1, 4], np.uint8), 11.0, [[11.0, 0.0, 1.1]]],
        ),
        (
            "cam_image",
            [[100], [100, 112], np.array([12, 44], np.uint8)],
            [True, 10.0, 1, 0, "[10.0]", np.array([12.5, 44.2], F)],
            [
                np.array([1, 2], np.uint32),
                np.array([1, 2], np.uint64),
                [12456, 41233544],
                [1.0, 244.0],
                [10, 1.0],
                [[11, 0, 1]],
            ],
        ),
        (
            "test_uint32_type",
            [100, 1, 0],
            [True, 10.0, "[10.0]", [10.0, 12.0], [10, 11], -12],
            [100.0, "100", True],
        ),
        (
            "parent",
            [100, 3689348814741910323, 0],
            [True, 10.0, "[10.0]", [10, 11], -12],
            [-12, True, 1.0],
        ),
        (
            "test_uint64_vec_type",
            [[256], [100, 112], np.array([12, 44], np.uint64)],
            [True, 10.0, 1, "[10.0]", np.array([12.5], F)],
            [
                np.array([1, 2], np.uint32),
                np.array([1.5], F),
                [1.0, 244.0],
                [10, 1.0],
                [[11, 0, 1]],
            ],
        ),
        (
            "test_vec3_type",
            [[10.0, 1.0, 0.0], (10.0, 11.1, 11.1), np.array([1.2, 4.4, 0.0], F)],
            [True, 10.0, 1, [10], "[10.0]", [10, 12, 22], np.array([12, 44, 0], np.uint8)],
            [
                [10, 11],
                11.0,
                [[11.0, 0.0, 0.0]],
                np.array([1.2], F),
                (10.0, 11.1, 11.1, 1.0),
                (10.0, 11.1),
            ],
        ),
    ],
)
def test_an_attribute_takes_the_values_its_names_cortex_type_takes(
    name, good, bad_attributes, bad_values
):
    """CORTEX's VariantCastTest, case by case: what goes into a typed attribute and what is a
    TypeError."""
    node = Node(12, "root", "elmundo")
    for value in good:
        node.attrs[name] = Attribute(value, 1)
        node.attrs[name].value = value
    for value in bad_attributes:
        with pytest.raises(TypeError):
            node.attrs[name] = Attribute(value, 1)
    for value in bad_values:
        with pytest.raises(TypeError):
            node.attrs[name].value = value
    with pytest.raises(TypeError):
        Attribute([10, "a"], 1)  # no kind of value at all


def test_rt_attributes_of_a_symbolic_edge_are_ordinary_attributes(g):
    edge = Edge(4, 2, "in", 12)
    edge.attrs["rt_translation"] = Attribute([1.0, 2.0, 3.0])
    assert g.insert_or_assign_edge(edge)
    read = g.get_edge(2, 4, "in")
    assert list(read.attrs["rt_translation"].value) == [1.0, 2.0, 3.0]
    read.attrs["rt_translation"].value = [4.0, 5.0, 6.0]
    assert g.insert_or_assign_edge(read)
    assert g._graph.edge(2, 4, "in").attrs["rt_translation"] == [4.0, 5.0, 6.0]
    del read.attrs["rt_translation"]
    assert g.insert_or_assign_edge(read) and "rt_translation" not in g._graph.edge(2, 4, "in").attrs
