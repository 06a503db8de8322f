"""Each rule of the graph model, one at a time: accepted when kept, rejected by name when broken."""

import math

import numpy as np
import pytest

from dsr_graph.exceptions import LookupFailed, RuleViolation
from dsr_graph.model.graph import Graph
from dsr_graph.model.vocabulary import Vocabulary

from invariants import assert_invariants

IDENTITY = {"matrix": np.eye(4).tolist()}


def rule_of(call):
    with pytest.raises(RuleViolation) as info:
        call()
    return info.value.violation.rule


@pytest.fixture
def g():
    graph = Graph()
    graph.insert_node("room", "room", id=1)
    graph.insert_node("robot", "robot", id=2)
    graph.insert_node("person", "person", id=3)
    graph.insert_node("speaking", "state", id=4)
    graph.insert_edge(
        "room", "robot", "RT", rt={"translation": [1, 0, 0], "rotation_euler_xyz": [0, 0, 0]}
    )
    graph.insert_edge(
        "room", "person", "RT", rt={"translation": [0, 2, 0], "rotation_euler_xyz": [0, 0, 0]}
    )
    graph.insert_edge("robot", "speaking", "is_not")
    return graph


def test_nodes_have_unique_ids_and_names(g):
    assert rule_of(lambda: g.insert_node("robot", "robot")) == "unique-name"
    assert rule_of(lambda: g.insert_node("other", "robot", id=2)) == "unique-id"
    node = g.insert_node("other", "robot")
    assert node.id == 5  # next free id
    assert g.node("other") is g.node(5)
    assert_invariants(g)


def test_node_names_must_be_printable_and_trimmed(g):
    for bad in ["", " robot2", "a\nb", "x" * 300, 7]:
        assert rule_of(lambda bad=bad: g.insert_node(bad, "robot")) == "node-name"


def test_types_come_from_the_vocabulary(g):
    assert rule_of(lambda: g.insert_node("ufo", "spaceship")) == "unknown-node-type"
    assert rule_of(lambda: g.insert_edge("robot", "person", "loves")) == "unknown-edge-type"
    assert rule_of(lambda: g.set_node_attrs("robot", {"flavour": "x"})) == "unknown-attribute"


def test_the_vocabulary_can_be_extended_with_data(tmp_path):
    path = tmp_path / "vocab.json"
    path.write_text(
        '{"format": "dsr-vocabulary", "version": 1, "extends": "default",'
        ' "node_types": {"spaceship": "a ship"}, "edge_types": {"loves": "x"},'
        ' "attributes": {"flavour": "string"}}'
    )
    g = Graph(Vocabulary.load(path))
    g.insert_node("ufo", "spaceship", attrs={"flavour": "mint"})
    g.insert_node("robot", "robot")
    g.insert_edge("ufo", "robot", "loves")
    assert g.node("ufo").attrs == {"flavour": "mint"}


def test_attribute_values_are_typed(g):
    g.set_node_attrs("robot", {"level": 3, "pos_x": 2, "collidable": True, "options": ["a", "b"]})
    assert g.node("robot").attrs["pos_x"] == 2.0 and isinstance(
        g.node("robot").attrs["pos_x"], float
    )
    assert rule_of(lambda: g.set_node_attrs("robot", {"level": 2.5})) == "attribute-type"
    assert rule_of(lambda: g.set_node_attrs("robot", {"level": True})) == "attribute-type"
    assert rule_of(lambda: g.set_node_attrs("robot", {"collidable": 1})) == "attribute-type"
    assert rule_of(lambda: g.set_node_attrs("robot", {"pos_x": math.nan})) == "attribute-type"
    assert rule_of(lambda: g.set_node_attrs("robot", {"options": ["a", 1]})) == "attribute-type"
    assert rule_of(lambda: g.set_node_attrs("robot", {"cam_rgb": [1, 256]})) == "attribute-type"
    assert rule_of(lambda: g.set_node_attrs("robot", {"parent": -1})) == "attribute-type"


def test_versions_count_changes(g):
    robot = g.node("robot")
    assert robot.version == 1
    g.set_node_attrs("robot", {"level": 1})
    g.remove_node_attrs("robot", ["level"])
    assert robot.version == 3
    assert rule_of(lambda: g.remove_node_attrs("robot", ["level"])) == "attribute-missing"
    edge = g.edge("robot", "speaking", "is_not")
    g.set_edge_attrs("robot", "speaking", "is_not", {"text": "hi"})
    assert edge.version == 2


def test_no_self_loops(g):
    assert rule_of(lambda: g.insert_edge("robot", "robot", "is_with")) == "no-self-loop"
    assert rule_of(lambda: g.insert_edge("robot", "robot", "RT", rt=IDENTITY)) == "no-self-loop"


def test_several_types_per_pair_but_each_once(g):
    g.insert_edge("person", "robot", "is_with")
    g.insert_edge("person", "robot", "can")
    assert rule_of(lambda: g.insert_edge("person", "robot", "is_with")) == "edge-unique"
    # an edge says nothing about its inverse
    assert g.edge("robot", "person", "is_with") is None
    g.insert_edge("robot", "person", "is_with")
    assert_invariants(g)


def test_edges_need_existing_ends(g):
    assert rule_of(lambda: g.insert_edge("robot", "ghost", "is_with")) == "node-missing"
    assert rule_of(lambda: g.delete_edge("robot", "person", "is_with")) == "edge-missing"


def test_rt_edges_hold_rigid_transforms(g):
    g.insert_node("cam", "rgbd")
    reflection = np.diag([1.0, 1.0, -1.0, 1.0]).tolist()
    scaled = np.diag([2.0, 2.0, 2.0, 1.0]).tolist()
    for rt in [
        None,
        {"matrix": reflection},
        {"matrix": scaled},
        {"matrix": [[1, 0], [0, 1]]},
        {"translation": [0, 0], "rotation_euler_xyz": [0, 0, 0]},
        {"translation": [0, 0, 0], "quaternion_wxyz": [2, 0, 0, 0]},
        {"translation": [0, 0, 0]},
    ]:
        assert rule_of(lambda rt=rt: g.insert_edge("robot", "cam", "RT", rt=rt)) == "rt-rigid"
    assert rule_of(lambda: g.insert_edge("robot", "cam", "has", rt=IDENTITY)) == "rt-rigid"
    # within tolerance: float32 angles round-tripped through JSON are accepted
    nearly = np.eye(4)
    nearly[0, 1] = 1e-9
    g.insert_edge("robot", "cam", "RT", rt={"matrix": nearly.tolist()})
    assert_invariants(g)


def test_rt_single_parent_and_acyclic(g):
    assert (
        rule_of(lambda: g.insert_edge("person", "robot", "RT", rt=IDENTITY)) == "rt-single-parent"
    )
    g.insert_node("cam", "rgbd")
    g.insert_edge("robot", "cam", "RT", rt=IDENTITY)
    # cam -> room would close room -> robot -> cam -> room
    assert rule_of(lambda: g.insert_edge("cam", "room", "RT", rt=IDENTITY)) == "rt-acyclic"
    assert rule_of(lambda: g.insert_edge("robot", "room", "RT", rt=IDENTITY)) == "rt-acyclic"


def test_rt_edges_form_one_tree_checked_at_the_end_of_a_transaction(g):
    g.insert_node("a", "transform")
    g.insert_node("b", "transform")
    with pytest.raises(RuleViolation) as info:
        with g.atomic():
            g.insert_edge("a", "b", "RT", rt=IDENTITY)  # a second tree, rooted at 'a'
    assert info.value.violation.rule == "rt-single-tree"
    assert "'a'" in str(info.value) and "'room'" in str(info.value)
    assert g.edge("a", "b", "RT") is None
    with g.atomic():  # joined to the tree in the same transaction: fine
        g.insert_edge("a", "b", "RT", rt=IDENTITY)
        g.insert_edge("robot", "a", "RT", rt=IDENTITY)
    assert_invariants(g)


def test_deleting_a_node_deletes_its_edges_but_never_orphans_a_subtree(g):
    g.insert_node("cam", "rgbd")
    g.insert_edge("robot", "cam", "RT", rt=IDENTITY)
    with pytest.raises(RuleViolation) as info:
        with g.atomic():
            g.delete_node("robot")
    assert info.value.violation.rule == "rt-orphan" and "'cam'" in info.value.violation.message
    assert (
        g.edge("robot", "cam", "RT") is not None
        and g.edge("robot", "speaking", "is_not") is not None
    )
    with g.atomic():
        g.delete_node("cam")
        g.delete_node("robot")
    assert "robot" not in g and g.edge_count() == 1
    assert_invariants(g)


def test_geometric_nodes_are_those_in_the_rt_tree(g):
    assert g.is_geometric("robot") and g.is_geometric("room")
    assert not g.is_geometric("speaking")
    with pytest.raises(LookupFailed, match="not geometric"):
        g.transform("room", "speaking")
    with pytest.raises(LookupFailed, match="no node"):
        g.transform("room", "ghost")
