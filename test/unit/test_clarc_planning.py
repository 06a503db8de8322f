"""PELEA's planning domain and Monitoring: the real planner (pyperplan) on the PDDL domain, from
the start and from each kind of deviation."""

import pytest
from barthel_items import DEFINITION, ORDER

from clarc_agents.pelea.decision_support import NoPlan
from clarc_agents.pelea.questionnaire_executive import plan
from clarc_agents.questionnaire import monitoring
from clarc_agents.questionnaire.planning import initial_state


def names(steps):
    return [str(s) for s in steps]


def test_a_whole_test_from_start():
    steps = names(plan(initial_state(person_present=True, definition=DEFINITION), DEFINITION))
    assert steps[:6] == [
        "(greet)",
        "(explain)",
        "(introduce feeding)",
        "(describe-options feeding)",
        "(ask feeding)",
        "(await-answer feeding)",
    ]
    for item in ORDER:  # every item introduced, described, asked and awaited, in order
        assert steps.index(f"(introduce {item})") < steps.index(f"(await-answer {item})")
    assert [s for s in steps if s.startswith("(introduce")] == [f"(introduce {i})" for i in ORDER]
    assert steps[-2:] == ["(say-goodbye stairs)", "(store-result)"]
    assert "(call-clinician)" not in steps


def test_nobody_in_front_of_the_robot_at_start():
    assert names(plan(initial_state(person_present=False, definition=DEFINITION), DEFINITION))[
        :3
    ] == [
        "(ask-to-sit)",
        "(wait-for-person)",
        "(greet)",
    ]


def started(*extra, drop=()):
    state = set(initial_state(True, DEFINITION)) | {"(greeted)", "(explained)"} | set(extra)
    return frozenset(state - set(drop))


def test_silence_then_options_again_then_skip():
    state = started("(asked feeding)", drop=["(pending feeding)"])
    state = monitoring.window_failed(state, "feeding", 1, "no_answer")
    assert names(plan(state, DEFINITION))[:3] == [
        "(options-again feeding)",
        "(await-answer-again feeding)",
        "(next-item feeding bathing)",
    ]
    state = monitoring.window_failed(state | {"(retry-asked feeding)"}, "feeding", 2, "no_answer")
    assert names(plan(state, DEFINITION))[:2] == [
        "(skip-item feeding)",
        "(next-item feeding bathing)",
    ]


def test_not_understood_then_clarify():
    state = monitoring.window_failed(
        started("(asked dressing)", "(current dressing)", drop=["(current feeding)"]),
        "dressing",
        1,
        "not_understood",
    )
    assert names(plan(state, DEFINITION))[:2] == [
        "(clarify dressing)",
        "(await-answer-again dressing)",
    ]


def test_asking_to_skip_closes_the_item_at_once():
    state = monitoring.window_failed(started("(asked feeding)"), "feeding", 1, "skip")
    assert names(plan(state, DEFINITION))[0] == "(skip-item feeding)"


def test_person_lost_asks_to_sit_and_starts_the_item_again():
    state = started(
        "(described bowels)", "(current bowels)", drop=["(current feeding)", "(pending bowels)"]
    )
    state = monitoring.person_lost(state, "bowels")
    steps = names(plan(state, DEFINITION))
    assert steps[:4] == [
        "(ask-to-sit)",
        "(wait-for-person)",
        "(introduce bowels)",
        "(describe-options bowels)",
    ]


def test_two_unanswered_call_the_clinician_before_going_on():
    state = monitoring.clinician_needed(started("(closed feeding)"))
    assert names(plan(state, DEFINITION))[:2] == ["(call-clinician)", "(next-item feeding bathing)"]


def test_an_impossible_goal_is_reported():
    with pytest.raises(NoPlan):
        plan(frozenset({"(clinician-ok)"}), DEFINITION)  # not started: nothing can happen
