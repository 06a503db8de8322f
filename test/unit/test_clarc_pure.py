"""CLARC's pure pieces: Barthel scoring, answer understanding, scenario files, the patient's
script, and the results store."""

import sqlite3

import pytest
from barthel_items import BY_KEY, DEFINITION, ITEMS, MAX_TOTAL, ORDER, band

from clarc_agents.exceptions import ScenarioError
from clarc_agents.questionnaire.answers import understand
from clarc_agents.questionnaire.record import QuestionnaireRecord
from clarc_agents.questionnaire.sentences import ASK
from clarc_sim.exceptions import InvalidResult
from clarc_sim.hospital.results_store import ResultsStore
from clarc_sim.patient import script
from clarc_sim.patient.scenario import parse
from clarc_sim.patient.script import PatientScript

GARBLED = script.GARBLED["en"]


def test_barthel_items_and_points_follow_mahoney_and_barthel():
    assert ORDER == (
        "feeding",
        "bathing",
        "grooming",
        "dressing",
        "bowels",
        "bladder",
        "toilet_use",
        "transfers",
        "mobility",
        "stairs",
    )
    assert {i.key: i.points for i in ITEMS} == {
        "feeding": (0, 5, 10),
        "bathing": (0, 5),
        "grooming": (0, 5),
        "dressing": (0, 5, 10),
        "bowels": (0, 5, 10),
        "bladder": (0, 5, 10),
        "toilet_use": (0, 5, 10),
        "transfers": (0, 5, 10, 15),
        "mobility": (0, 5, 10, 15),
        "stairs": (0, 5, 10),
    }
    assert MAX_TOTAL == 100


@pytest.mark.parametrize(
    "total, expected",
    [
        (0, "total"),
        (20, "total"),
        (21, "severe"),
        (60, "severe"),
        (61, "moderate"),
        (90, "moderate"),
        (91, "slight"),
        (99, "slight"),
        (100, "independent"),
    ],
)
def test_dependency_bands(total, expected):
    assert band(total) == expected


def test_record_totals_only_answered_items():
    r = QuestionnaireRecord(DEFINITION, "Carlos", "t0")
    r.answer("feeding", 10, "voice")
    r.items["grooming"].attempts = 2
    r.give_up("grooming")
    assert r.total == 10 and r.unanswered == ["grooming"]
    with pytest.raises(ValueError):
        r.answer("bathing", 10, "voice")  # not an option of bathing
    doc = r.to_json()
    assert doc["items"][2] == {
        "item": "grooming",
        "points": None,
        "via": None,
        "attempts": 2,
        "max": 5,
        "needs_clinician": False,
    }


def test_every_option_is_understood_from_its_own_words():
    for it in ITEMS:
        for n, o in enumerate(it.options, 1):
            assert understand(it, o.says).points == o.points
            assert understand(it, o.text).points == o.points
            assert understand(it, f"option {n}").points == o.points


@pytest.mark.parametrize(
    "text, kind",
    [
        (GARBLED, "not_understood"),
        ("", "not_understood"),
        ("please skip this one", "skip"),
        ("next question", "skip"),
        ("yes and no", "not_understood"),
    ],
)
def test_what_is_not_an_answer(text, kind):
    assert understand(BY_KEY["bowels"], text).kind == kind


def test_scenario_defaults_and_errors_name_the_line():
    s = parse("patient: Carlos\nitems:\n  stairs: {answer: 5, via: touch, leave: 2.0}\n")
    assert (s.plan("stairs").answer, s.plan("stairs").via, s.plan("stairs").leave) == (
        5,
        "touch",
        2.0,
    )
    assert (s.plan("feeding").answer, s.plan("feeding").via) == (10, "voice")
    for text, fragment in [
        (
            "patient: C\nitems:\n  feeding: {answer: 7}\n",
            "x.yaml:3: feeding: answer 7 is not an option",
        ),
        ("patient: C\nitems:\n  cooking: {answer: 5}\n", "x.yaml:3: unknown item 'cooking'"),
        (
            "patient: C\nitems:\n  feeding:\n    answer: 5\n    mood: happy\n",
            "x.yaml:5: feeding: unknown key 'mood'",
        ),
        ("patient: C\nitems:\n  feeding: {via: shouting}\n", "via must be one of"),
        ("patient: C\nitems:\n  feeding: {first: loud}\n", "first must be one of"),
        ("patient: C\nitems:\n  feeding: {leave: -1}\n", "leave is a number"),
        ("patient: C\nweather: rain\n", "x.yaml:2: unknown key 'weather'"),
    ]:
        with pytest.raises(ScenarioError) as info:
            parse(text, "x.yaml")
        assert fragment in str(info.value)


def test_patient_script_follows_the_scenario():
    s = parse(
        "patient: C\nitems:\n  feeding: {answer: 5, via: voice, first: garbled}\n"
        "  bathing: {answer: 0, via: touch, first: silence}\n  grooming: {via: silence, leave: 2}\n"
    )
    p = PatientScript(s, DEFINITION, reaction=1.0)
    assert p.heard("Question 1 of 10, Feeding. Can you eat by yourself?", "start") == []
    [a] = p.heard(ASK + " Say it, or touch it on the screen.", "end")
    assert (a.kind, a.text) == ("say", GARBLED)
    [a] = p.heard("Sorry, I did not understand. Can you eat by yourself?", "end")
    assert (a.kind, a.text) == ("say", "I need some help cutting the food")
    # the answer read back: yes when it is the option meant (worth 5), no otherwise
    [a] = p.heard("I heard: I need help cutting or spreading. Is that right? Say yes or no", "end")
    assert (a.kind, a.text) == ("say", "Yes, that's right.")
    [a] = p.heard("I heard: I eat by myself. Is that right? Say yes or no", "end")
    assert (a.kind, a.text) == ("say", "No.")
    p.heard("Question 2 of 10, Bathing. Can you bathe or shower by yourself?", "start")
    assert p.heard(ASK, "end") == []  # silent on the first try
    [a] = p.heard("Let me say the options again. ...", "end")
    assert (a.kind, a.points) == ("tap", 0)
    [a] = p.heard(
        "Question 3 of 10, Grooming. "
        "Can you wash your face, comb your hair and brush your teeth by yourself?",
        "start",
    )
    assert (a.kind, a.seconds) == ("leave", 2.0)


def result(**changes):
    r = QuestionnaireRecord(DEFINITION, "Carlos", "2026-11-24T10:00:00")
    for k in ORDER:
        r.answer(k, max(BY_KEY[k].points), "voice")
        r.items[k].attempts = 1
    r.finished = "2026-11-24T10:10:00"
    doc = r.to_json()
    doc.update(changes)
    return doc


def test_results_store_keeps_each_test_once_and_refuses_wrong_sums(tmp_path):
    store = ResultsStore(tmp_path / "db.sqlite")
    first = store.store(result())
    assert store.store(result()) == first  # the same test again: kept once
    assert len(store.tests()) == 1 and store.tests()[0]["total"] == 100
    with pytest.raises(InvalidResult, match="do not match"):
        store.store(result(total=90, started="other"))
    with pytest.raises(InvalidResult, match="in order"):
        store.store(result(items=result()["items"][::-1], started="x"))
    store.notify("clinician_called", "please come")
    assert store.notifications()[0]["kind"] == "clinician_called"
    store.close()
    # committed before acknowledged: another connection sees it at once
    rows = sqlite3.connect(tmp_path / "db.sqlite").execute("SELECT COUNT(*) FROM items").fetchone()
    assert rows == (10,)


def test_a_result_sent_again_is_stored_once_and_told_once(tmp_path):
    store = ResultsStore(tmp_path / "db.sqlite")
    result = QuestionnaireRecord(DEFINITION, "Carlos", "2026-11-24T10:00:00").to_json()
    first, again = store.store(result), store.store(result)
    assert first == again and len(store.tests()) == 1
    assert not store.notified("result_stored", first)
    store.notify("result_stored", "stored", first)
    assert store.notified("result_stored", first)


def test_a_store_written_before_notifications_named_their_test_opens(tmp_path):
    path = tmp_path / "old.sqlite"
    old = sqlite3.connect(path)
    old.executescript(
        "CREATE TABLE notifications (id INTEGER PRIMARY KEY AUTOINCREMENT, time TEXT NOT NULL,"
        " kind TEXT NOT NULL, message TEXT NOT NULL);"
        "INSERT INTO notifications (time, kind, message) VALUES ('t', 'clinician_called', 'hi');"
    )
    old.commit()
    old.close()
    store = ResultsStore(path)
    assert store.notifications()[0]["message"] == "hi"
    store.notify("result_stored", "stored", 1)
    assert store.notified("result_stored", 1)


def test_the_chaos_plan_kills_each_process_in_turn_at_seeded_moments():
    from clarc_sim.console.chaos import PROCESSES, plan

    runs = plan(7, runs=4, kills=3, processes=list(PROCESSES), earliest=1.0, latest=30.0)
    assert plan(7, 4, 3, list(PROCESSES), 1.0, 30.0) == runs  # the seed replays it
    killed = [kill.process for run in runs for kill in run.kills]
    assert sorted(killed[:6]) == sorted(killed[6:]) == sorted(PROCESSES)
    for run in runs:
        moments = [kill.moment for kill in run.kills]
        assert len({kill.process for kill in run.kills}) == 3 and moments == sorted(moments)
        assert all(1.0 <= m <= 30.0 for m in moments)
