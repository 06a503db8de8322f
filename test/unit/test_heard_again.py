"""A words or serial answer heard not for sure, asked again and heard the same: two hearings
that agree are sure (questionnaire/agreement.py), through Speech's rules and PELEA's record in
the DSR, a restart of either between the two windows included."""

from __future__ import annotations

import pytest

from clarc_agents import definitions
from clarc_agents.questionnaire.agreement import FLOOR, heard_again, independent, same_answer
from clarc_agents.questionnaire.orientation import values

from local_clarc import Patient, Robot

WORDS = "Apple, table, penny."


def _mmse_item(key: str):
    from datetime import date

    return definitions.load("mmse").filled(values(date(2026, 12, 1))).item(key)


def test_the_same_answer_is_the_same_points_for_the_same_parts_something_credited():
    recall, attention = _mmse_item("recall"), _mmse_item("attention")
    assert same_answer(recall, "apple, table, penny", "Apple table and penny.")
    assert not same_answer(recall, "apple, table, penny", "apple, table")
    assert not same_answer(recall, "apple, table", "table, penny")  # 2 points each, not the same
    assert not same_answer(recall, "a car, a dog", "a car, a dog")  # nothing credited
    assert same_answer(attention, "93 86 79 72 65", "ninety three, eighty six, 79, 72, 65")
    assert not same_answer(attention, "93 86 82 73", "93 86 80 73")
    # the start said before the numbers, or not: scored alike, one answer
    assert same_answer(attention, "100 minus seven is 93, minus seven is 86", "93, 86.")
    assert not same_answer(attention, "100, 93, 86", "93, 86, 79")
    assert not same_answer(attention, "100.", "One hundred.")  # the start alone: no answer


def test_two_agreeing_hearings_combine_and_each_must_reach_the_floor():
    recall, attention = _mmse_item("recall"), _mmse_item("attention")
    assert independent(0.45, 0.45) == pytest.approx(0.6975)
    both = heard_again(recall, [("apple and penny", 0.6), (WORDS, 0.45)], WORDS, 0.45)
    assert both == (pytest.approx(0.6975), WORDS)
    assert heard_again(recall, [(WORDS, FLOOR - 0.01)], WORDS, 0.45) is None
    assert heard_again(recall, [(WORDS, 0.45)], WORDS, FLOOR - 0.01) is None
    assert heard_again(recall, [("apple, table", 0.45)], WORDS, 0.45) is None
    # a choose item is confirmed by its read-back instead
    barthel = definitions.load("barthel").item("feeding")
    assert heard_again(barthel, [("two", 0.45)], "two", 0.45) is None
    serial = [("93, 86, 79, 72, 65.", 0.45)]
    assert heard_again(attention, serial, "93 86 79 72 65", 0.45)[0] == pytest.approx(0.6975)
    # "93, 80, 80, 73." for "... eighty seven, eighty, seventy three", heard twice (the speech
    # benchmark, once Whisper counted other spellings): the first at 0.40 is no second hearing
    assert heard_again(attention, [("93, 80, 80, 73.", 0.40)], "93, 80, 80, 73.", 0.5) is None


def _recall(result):
    return next(i for i in result["items"] if i["item"] == "recall")


def test_an_answer_heard_twice_the_same_counts_and_a_different_one_goes_to_the_clinician():
    robot = Robot(Patient(answers={"recall": [("heard", WORDS, 0.45)] * 2}), test="mmse")
    recall = _recall(robot.run_test())
    assert (recall["points"], recall["via"], recall["needs_clinician"]) == (3, "voice", False)
    assert recall["audio"] == ["clips/recall-1.wav", "clips/recall-2.wav"]
    node = robot.pelea_link.graph.node("item_recall").attrs
    assert node["outcomes"] == ["not_understood", "answered"]
    assert node["hearings"] == [WORDS] and node["hearing_confidences"] == [0.45]

    changed = [("heard", WORDS, 0.45), ("heard", "Apple, table.", 0.45)]
    robot = Robot(Patient(answers={"recall": changed}), test="mmse")
    recall = _recall(robot.run_test())
    assert (recall["points"], recall["needs_clinician"]) == (None, True)

    unsure = [("heard", WORDS, 0.35), ("heard", WORDS, 0.45)]  # the first under the floor
    recall = _recall(Robot(Patient(answers={"recall": unsure}), test="mmse").run_test())
    assert (recall["points"], recall["needs_clinician"]) == (None, True)


@pytest.mark.parametrize("agent", ["pelea", "speech"])
def test_the_first_hearing_outlives_a_restart_between_the_two(agent):
    patient = Patient(answers={"recall": [("heard", WORDS, 0.45)] * 2})
    robot = Robot(patient, test="mmse")
    robot.run_test()
    windows = [e for e in robot.port.events if e.get("item") == "recall"]
    first = next(e["t"] for e in windows if e["event"] == "not_understood")
    second = [e["t"] for e in windows if e["event"] == "listening"][1]
    robot = Robot(patient, test="mmse")
    robot.bus.after((first + second) / 2, getattr(robot, f"restart_{agent}"))
    recall = _recall(robot.run_test())
    assert (recall["points"], recall["needs_clinician"]) == (3, False)
    assert robot.pelea_link.graph.node("item_recall").attrs["hearings"] == [WORDS]
