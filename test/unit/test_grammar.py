"""Grammar rules as data: parsing, matching with variables and negation, the CAS preconditions
of the during write, and the engine's once-per bookkeeping (Algorithm 2 without ROS)."""

import pytest

from dsr_graph.exceptions import GrammarError, TransactionRejected
from dsr_graph.model.graph import Graph
from dsr_graph.model.transaction import apply_ops
from dsr_graph.rules.engine import GrammarEngine
from dsr_graph.rules.matching import match
from dsr_graph.rules.syntax import Rule, load_rules

SPEECH = [
    {
        "name": "start_speaking",
        "when": [
            {"edge": ["robot", "speaking", "is_not"]},
            {
                "edge": ["test", "test_part", "is_in"],
                "attrs": {"text": "$text", "sentence_id": "$sid"},
            },
            {"no_edge": ["_", "robot", "has"]},
        ],
        "once_per": ["$sid"],
        "during": [
            {"delete_edge": ["robot", "speaking", "is_not"]},
            {"insert_edge": ["robot", "speaking", "is"]},
        ],
        "claim": [{"from": "robot", "to": "speaking"}],
        "process": "say",
        "after": {
            "done": [
                {"delete_edge": ["robot", "speaking", "is"]},
                {"insert_edge": ["robot", "speaking", "finish"]},
            ],
            "interrupted": [
                {"delete_edge": ["robot", "speaking", "is"]},
                {"insert_edge": ["robot", "speaking", "is_not"]},
            ],
        },
    },
    {
        "name": "waiting_answer",
        "when": [{"edge": ["$p", "answer", "can"]}, {"node": "$p", "type": "person"}],
        "during": [
            {"delete_edge": ["$p", "answer", "can"]},
            {"insert_edge": ["$p", "answer", "waiting"]},
        ],
    },
]


@pytest.fixture
def g():
    graph = Graph()
    apply_ops(
        graph,
        [
            {"op": "insert_node", "name": n, "type": t}
            for n, t in [
                ("robot", "robot"),
                ("speaking", "state"),
                ("test", "test"),
                ("test_part", "test_part"),
                ("carlos", "person"),
                ("answer", "state"),
            ]
        ]
        + [
            {"op": "insert_edge", "from": "robot", "to": "speaking", "type": "is_not"},
            {
                "op": "insert_edge",
                "from": "test",
                "to": "test_part",
                "type": "is_in",
                "attrs": {"text": "Hello", "sentence_id": 1},
            },
            {"op": "insert_edge", "from": "carlos", "to": "answer", "type": "can"},
        ],
    )
    return graph


def test_match_binds_variables_and_honours_negation(g):
    rules = load_rules(SPEECH)
    found = list(match(g, rules[0].when))
    assert found == [{"$text": "Hello", "$sid": 1}]
    assert list(match(g, rules[1].when)) == [{"$p": "carlos"}]
    apply_ops(
        g,
        [
            {"op": "insert_node", "name": "x", "type": "person"},
            {"op": "insert_edge", "from": "x", "to": "robot", "type": "has"},
        ],
    )
    assert list(match(g, rules[0].when)) == []


def test_during_is_a_compare_and_set_on_the_before_pattern(g):
    engine = GrammarEngine(load_rules(SPEECH))
    firing = next(f for f in engine.search(g) if f.rule.name == "start_speaking")
    tx = firing.during_tx()
    assert {"check": "edge_exists", "from": "robot", "to": "speaking", "type": "is_not"} in tx[
        "preconditions"
    ]
    assert {
        "check": "attr_equals",
        "from": "test",
        "to": "test_part",
        "type": "is_in",
        "attr": "text",
        "value": "Hello",
    } in tx["preconditions"]
    assert tx["claim"] == [{"from": "robot", "to": "speaking"}] and "priority" not in tx
    apply_ops(g, tx["ops"], tx["preconditions"])
    assert g.edge("robot", "speaking", "is")
    with pytest.raises(TransactionRejected):  # a second agent's identical write loses
        apply_ops(g, tx["ops"], tx["preconditions"])
    after = firing.after_tx("done")
    assert after["release"] == [{"from": "robot", "to": "speaking"}]
    apply_ops(g, after["ops"], after["preconditions"])
    assert g.edge("robot", "speaking", "finish")


def test_once_per_fires_again_only_for_a_new_sentence(g):
    engine = GrammarEngine(load_rules(SPEECH)[:1])
    [firing] = engine.search(g)
    engine.started(firing)
    assert engine.search(g) == []  # in flight
    engine.handled(firing)
    engine.finished(firing)
    assert engine.search(g) == []  # same sentence_id: "label == label_back"
    apply_ops(
        g,
        [
            {
                "op": "set_edge_attrs",
                "from": "test",
                "to": "test_part",
                "type": "is_in",
                "attrs": {"text": "Hello", "sentence_id": 2},
            }
        ],
    )
    assert [f.bindings["$sid"] for f in engine.search(g)] == [2]  # the same text, said again


def test_after_requires_the_during_state_to_hold(g):
    engine = GrammarEngine(load_rules(SPEECH)[:1])
    [firing] = engine.search(g)
    tx = firing.during_tx()
    apply_ops(g, tx["ops"], tx["preconditions"])
    # the person leaves: something resets robot is -> is_not before the sentence ends
    apply_ops(
        g,
        [
            {"op": "delete_edge", "from": "robot", "to": "speaking", "type": "is"},
            {"op": "insert_edge", "from": "robot", "to": "speaking", "type": "is_not"},
        ],
    )
    after = firing.after_tx("done")
    with pytest.raises(TransactionRejected, match="precondition"):
        apply_ops(g, after["ops"], after["preconditions"])


def test_outcome_bindings_reach_the_after_write(g):
    rule = Rule.parse(
        {
            "name": "listen",
            "when": [{"edge": ["$p", "answer", "waiting"]}],
            "during": [{"set_edge_attrs": ["$p", "answer", "waiting", {"attempts": 1}]}],
            "process": "listen",
            "after": [
                {"delete_edge": ["$p", "answer", "waiting"]},
                {"insert_edge": ["$p", "answer", "got", {"answer": "$points", "via": "$via"}]},
            ],
        }
    )
    apply_ops(
        g,
        [
            {"op": "delete_edge", "from": "carlos", "to": "answer", "type": "can"},
            {"op": "insert_edge", "from": "carlos", "to": "answer", "type": "waiting"},
        ],
    )
    [firing] = GrammarEngine([rule]).search(g)
    tx = firing.after_tx("done", {"points": 10, "via": "voice"})
    assert tx["ops"][1]["attrs"] == {"answer": 10, "via": "voice"}


@pytest.mark.parametrize(
    "doc, fragment",
    [
        ({"name": "r"}, "at least one pattern"),
        ({"name": "r", "when": [{"edge": ["a", "b"]}], "during": []}, "[from, to, type]"),
        (
            {"name": "r", "when": [{"edge": ["a", "b", "c"]}]},
            'needs a "during" write or a "process"',
        ),
        (
            {
                "name": "r",
                "when": [{"edge": ["a", "b", "c"]}],
                "during": [{"insert_edge": ["$x", "b", "c"]}],
            },
            "$x used but never bound",
        ),
        (
            {"name": "r", "when": [{"edge": ["a", "b", "c"]}], "during": [{"fly": 3}]},
            "cannot read fly",
        ),
        (
            {
                "name": "r",
                "when": [{"edge": ["a", "b", "c"]}],
                "during": [{"delete_node": "a"}],
                "after": [],
            },
            None,
        ),
        (
            {
                "name": "r",
                "when": [{"edge": ["a", "b", "c"]}],
                "during": [{"delete_node": "a"}],
                "after": {"done": []},
            },
            'needs a "process"',
        ),
        (
            {"name": "r", "when": [{"edge": ["a", "b", "c"]}], "colour": 1, "during": []},
            "unknown keys",
        ),
    ],
)
def test_malformed_rules_name_the_problem(doc, fragment):
    if fragment is None:
        Rule.parse(doc)
        return
    with pytest.raises(GrammarError, match=fragment.replace("[", r"\[").replace("$", r"\$")):
        Rule.parse(doc)


def test_rule_names_are_unique():
    with pytest.raises(GrammarError, match="unique"):
        load_rules([SPEECH[1], SPEECH[1]])
