"""The Speech, Panel and Person grammars on a local graph (the CLARC room), rule by rule."""

from pathlib import Path

import pytest
from barthel_items import DEFINITION

from clarc_agents.grammar_files import load_grammar
from clarc_agents.pelea import high_to_low
from clarc_agents.questionnaire.high_to_low import open_answer
from clarc_agents.questionnaire.sentences import ask, sit_down
from dsr_graph.exceptions import TransactionRejected
from dsr_graph.formats.world_files import read_world
from dsr_graph.model.transaction import apply_ops
from dsr_graph.rules.engine import GrammarEngine

ROOM = Path(__file__).resolve().parents[2] / "worlds" / "clarc_room.json"
POSE = {"translation": [0.9, 0, -0.4], "rotation_euler_xyz": [0, 0, 0]}


def engine(name):
    return GrammarEngine(load_grammar(name))


def run(graph, tx):
    apply_ops(graph, tx["ops"], tx.get("preconditions"))


@pytest.fixture
def room():
    world = read_world(ROOM)
    assert world.violations == []
    g = world.graph
    person = engine("person")
    [f] = person.signal(g, "seen", {"pose": POSE})
    assert f.rule.name == "first_sight"
    run(g, f.during_tx())
    return g


def fire(eng, graph, rule):
    [f] = [f for f in eng.search(graph) if f.rule.name == rule]
    run(graph, f.during_tx())
    return f


def test_person_rules_follow_the_kinect(room):
    person = engine("person")
    assert room.edge("person", "robot", "is_with") and room.rt_parent("person").name == "kinect"
    assert person.signal(room, "seen", {"pose": POSE}) == []  # already with the robot
    [f] = person.signal(room, "lost", {})
    run(room, f.during_tx())
    assert (
        room.edge("person", "robot", "is_with") is None
        and room.node("person").attrs["detected"] is False
    )
    [f] = person.signal(
        room, "seen", {"pose": {"translation": [1.0, 0, -0.4], "rotation_euler_xyz": [0, 0, 0]}}
    )
    assert f.rule.name == "person_back"
    run(room, f.during_tx())
    assert room.transform("kinect", "person")[0][3] == 1.0


def test_speech_says_a_new_sentence_once_and_stops_when_the_person_leaves(room):
    speech = engine("speech")
    run(room, high_to_low.say(room, ask(DEFINITION, "feeding"), 1))
    f = fire(speech, room, "start_speaking")
    assert f.bindings["$text"].startswith("Which option") and f.during_tx()["claim"] == [
        {"from": "robot", "to": "speaking"}
    ]
    speech.handled(f)
    speech.finished(f)
    assert [x.rule.name for x in speech.search(room)] == []  # same sentence: not again
    [f2] = engine("person").signal(room, "lost", {})
    run(room, f2.during_tx())
    fire(speech, room, "stop_speaking")
    assert room.edge("robot", "speaking", "is_not")
    after = f.after_tx("done", {"ended_at": 1.0})  # the interrupted sentence's "finish" is refused
    with pytest.raises(TransactionRejected):
        run(room, after)


def test_speech_does_not_stop_for_a_sentence_meant_for_nobody(room):
    speech = engine("speech")
    [f] = engine("person").signal(room, "lost", {})
    run(room, f.during_tx())
    run(room, high_to_low.say(room, sit_down(), 2))
    fire(speech, room, "start_speaking")
    assert [x.rule.name for x in speech.search(room)] == []


def test_listening_and_a_tap_race_for_one_answer(room):
    speech, panel = engine("speech"), engine("panel")
    run(room, open_answer(room, "feeding"))
    listen = fire(speech, room, "waiting_answer")
    [tap] = panel.signal(room, "tap", {"points": 5})
    run(room, tap.during_tx())
    got = room.edge("person", "answer", "got").attrs
    assert got == {"item": "feeding", "answer": 5.0, "via": "touch", "understood": True}
    with pytest.raises(TransactionRejected):  # speech's late answer loses
        run(
            room,
            listen.after_tx(
                "answered",
                {"points": 10, "heard": "I eat on my own", "confidence": 0.9, "audio": ""},
            ),
        )
    assert panel.signal(room, "tap", {"points": 10}) == []  # nothing awaited any more


def test_panel_shows_each_sentence_and_clears_when_the_person_leaves(room):
    panel = engine("panel")
    run(room, high_to_low.say(room, ask(DEFINITION, "stairs"), 1))
    f = fire(panel, room, "start_showing")
    assert f.bindings["$options"] == [
        "I cannot use stairs",
        "I need help on stairs",
        "I use stairs by myself",
    ]
    run(room, f.after_tx("done", {"ended_at": 1.0}))
    [lost] = engine("person").signal(room, "lost", {})
    run(room, lost.during_tx())
    fire(panel, room, "clear_panel")
    assert room.edge("robot", "showing", "is_not")


def test_a_window_left_open_by_a_lost_close_is_replaced_when_the_next_opens(room):
    run(room, open_answer(room, "feeding"))
    fire(engine("speech"), room, "waiting_answer")  # can -> waiting; the close never came
    run(room, open_answer(room, "bathing"))
    assert room.edge("person", "answer", "waiting") is None
    assert room.edge("person", "answer", "can").attrs == {"item": "bathing"}
