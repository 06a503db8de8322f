"""Questionnaire tests as data: the MMSE and the Lawton scale run end to end on the same
executive, planning domain and agents as the Barthel test (test/local_clarc.py: PELEA, Speech,
Panel and Person with their real grammars on a LocalBus), each answer earning what the patient
gave; their definitions, scenarios and results are checked as strictly as the Barthel test's."""

from datetime import date

import pytest

from clarc_agents import definitions
from clarc_agents.definitions import parse
from clarc_agents.exceptions import DefinitionError, ScenarioError
from clarc_agents.questionnaire.answers import touched_in_order, understand
from clarc_agents.questionnaire.orientation import values
from clarc_sim.exceptions import InvalidResult
from clarc_sim.hospital.results_store import ResultsStore
from clarc_sim.patient.answering import touches_for, words_for
from clarc_sim.patient.scenario import parse as parse_scenario

from local_clarc import Patient, Robot

MMSE_MAXIMA = {
    "orientation_time": 5,
    "orientation_place": 5,
    "registration": 3,
    "attention": 5,
    "recall": 3,
    "naming": 2,
    "repetition": 1,
    "command": 3,
    "reading": 1,
    "writing": 1,
    "copying": 1,
}


def items(result):
    return {i["item"]: (i["points"], i["via"], i["attempts"]) for i in result["items"]}


def test_the_mmse_has_its_items_maxima_and_bands():
    mmse = definitions.load("mmse")
    assert {i.key: i.max for i in mmse.items} == MMSE_MAXIMA and mmse.max_total == 30
    assert [mmse.band(t) for t in (0, 17, 18, 23, 24, 30)] == [
        "severe impairment",
        "severe impairment",
        "mild",
        "mild",
        "normal cognition",
        "normal cognition",
    ]
    assert [i.key for i in mmse.items if i.needs_clinician] == ["writing", "copying"]
    assert definitions.load("lawton").max_total == 8 and len(definitions.load("lawton").items) == 8


def test_orientation_is_scored_against_the_date_and_the_place():
    today = values(date(2026, 11, 24), ("Spain", "Andalusia", "Seville", "Virgen del Rocio", "1"))
    mmse = definitions.load("mmse").filled(today)
    time = mmse.item("orientation_time")
    assert understand(time, "2026, autumn, the 24th, Tuesday, November").points == 5
    assert understand(time, "2025, autumn, the 24th, Monday, November").points == 3
    assert understand(time, "I don't know").points == 0  # an answer, worth nothing
    assert understand(time, "mmh... the, eh... brr").kind == "not_understood"
    assert understand(mmse.item("orientation_place"), "Spain, Seville").points == 2
    assert values(date(2026, 3, 1))["season"] == ("spring",)
    with pytest.raises(DefinitionError, match="5 parts"):
        values(date(2026, 3, 1), ("Spain",))


@pytest.mark.parametrize(
    "said, points",
    [
        ("93, 86, 79, 72, 65", 5),
        ("93, 85, 78, 71, 64", 4),  # one slip costs one point: the rest follow from 85
        ("ninety three, eighty six, seventy nine", 3),
        ("a hundred, ninety-three, 86, 79, 72, 65", 5),  # the start said again
        ("90, 83, 76", 2),
        ("I don't know", 0),
    ],
)
def test_serial_sevens_score_each_number_against_the_one_said_before(said, points):
    attention = definitions.load("mmse").item("attention")
    assert understand(attention, said).points == points


def test_the_patient_earns_exactly_the_points_asked_on_every_item():
    mmse = definitions.load("mmse").filled(values(date(2026, 11, 24)))
    for item in mmse.items:
        for points in range(item.max + 1):
            if item.kind in ("words", "serial"):
                assert understand(item, words_for(item, points)).points == points, item.key
            if item.kind == "touches":
                assert touched_in_order(item, touches_for(item, points)) == points


def test_a_whole_mmse_runs_and_waits_for_the_clinician_for_the_drawings():
    result = Robot(test="mmse").run_test()
    assert result["test"] == "mmse" and [i["item"] for i in result["items"]] == list(MMSE_MAXIMA)
    by = items(result)
    assert by["reading"] == (1, "camera", 1) and by["command"] == (3, "touch", 1)
    assert by["writing"] == (None, "touch", 1) and by["copying"] == (None, "touch", 1)
    assert all(by[k] == (MMSE_MAXIMA[k], "voice", 1) for k in list(MMSE_MAXIMA)[:7])
    assert (
        result["total"] == 28
        and result["complete"] is False
        and result["band"] == "normal cognition"
    )
    assert {i["item"]: i["max"] for i in result["items"]} == MMSE_MAXIMA
    drawings = [i for i in result["items"] if i["needs_clinician"]]
    assert all(i["drawing"].startswith("M ") for i in drawings)


@pytest.mark.parametrize(
    "shapes, points",
    [
        (["circle", "square"], 2),
        (["square", "triangle", "star"], 2),
        (["triangle"], 1),
        (["star"], 0),
    ],
)
def test_a_three_stage_command_left_unfinished_is_scored_when_its_window_ends(shapes, points):
    """Fewer shapes than stages: nothing more comes, and the window's end scores what was done
    (each stage in order); all three, even with a wrong one, are scored at once."""
    patient = Patient(answers={"command": [("shapes", shapes)]})
    by = items(Robot(patient, test="mmse").run_test())
    assert by["command"] == (points, "touch", 1)


def test_each_mmse_item_earns_what_the_patient_gave_and_deviations_work_as_in_barthel():
    patient = Patient(
        answers={
            "orientation_time": ["garbled", ("voice", 3)],
            "attention": [("voice", 0)],
            "recall": [("voice", 2)],
            "command": [("touch", 1)],
            "reading": [("eyes", 0)],
            "writing": ["silence", "silence"],
        },
        leaves={"naming": 3.0},
    )
    robot = Robot(patient, test="mmse")
    result = robot.run_test()
    by = items(result)
    assert by["orientation_time"] == (3, "voice", 2)  # not understood first, then 3 right
    assert by["attention"] == (0, "voice", 1)  # "I don't know" is an answer worth 0
    assert by["recall"] == (2, "voice", 1) and by["command"] == (1, "touch", 1)
    assert by["reading"] == (0, "camera", 2)  # the eyes never closed, asked twice: 0 points
    assert by["writing"] == (None, None, 2) and result["unanswered"] == ["writing"]
    assert by["naming"] == (2, "voice", 1) and result["person_lost_count"] == 1
    assert result["total"] == 3 + 5 + 3 + 0 + 2 + 2 + 1 + 1 + 0
    assert "recall" in {e.get("item") for e in robot.port.events if e["event"] == "answer"}


def test_the_lawton_scale_is_a_data_file_only_and_runs_end_to_end():
    result = Robot(Patient(answers={"shopping": [("touch", 0)]}), test="lawton").run_test()
    assert result["test"] == "lawton" and len(result["items"]) == 8
    assert items(result)["shopping"] == (0, "touch", 1)
    assert result["total"] == 7 and result["band"] == "mostly independent"
    assert result["complete"] is True
    answers = {i["item"]: i["answer"] for i in result["items"]}
    assert answers["shopping"] == "I need someone with me, or I cannot shop"


def test_every_option_of_every_test_is_understood_from_what_a_patient_says():
    for test in definitions.tests():
        for language in definitions.languages(test):
            for item in definitions.load(test, language).items:
                for option in item.options:
                    for said in (option.says, option.text):  # and read back from the screen
                        assert understand(item, said).points == option.points, (
                            test,
                            language,
                            item.key,
                            said,
                        )


BAD_ITEMS = [
    ("  - {key: a, title: A, question: Q, kind: guess, ask: S}", "kind is one of"),
    ("  - {key: a, title: A, question: Q, kind: words, ask: S}", "missing parts"),
    (
        "  - {key: a, title: A, question: Q, kind: words, ask: S,"
        " parts: [{name: n, words: ['{x}']}]}",
        "unknown placeholder {x}",
    ),
    (
        "  - {key: a, title: A, question: Q, kind: touches, ask: S, shows: [star],"
        " parts: [{name: n, words: [circle]}]}",
        "shows lacks the target",
    ),
    ("  - {key: a, title: A, question: Q, kind: eyes, ask: S, shows: [X], points: 0}", ">= 1"),
    (
        "  - {key: a, title: A, question: Q, kind: serial, ask: S,"
        " parts: [{name: a, words: ['93']}, {name: b, words: ['85']}, {name: c, words: ['79']}]}",
        "go by one step",
    ),
]


@pytest.mark.parametrize("item, message", BAD_ITEMS)
def test_a_definition_with_a_wrong_item_is_refused_naming_the_line(item, message):
    text = (
        "format: clarc-test\nversion: 1\ntest: t\ntitle: T\nscoring: sum\n"
        "sentences: {greet: g, explain: e, goodbye: b}\n"
        "bands: [{name: all, min: 0, max: 1}]\nitems:\n" + item + "\n"
    )
    with pytest.raises(DefinitionError, match=message) as info:
        parse(text, "t.yaml")
    assert "t.yaml:9:" in str(info.value)


def test_mmse_scenarios_are_checked_strictly():
    s = parse_scenario(
        "test: mmse\npatient: Ana\nitems:\n  recall: {points: 2, via: voice}\n"
        "  reading: {points: 0, via: touch}\n  writing: {via: silence}\n"
    )
    assert (s.plan("recall").answer, s.plan("recall").via) == (2, "voice")
    assert (s.plan("reading").answer, s.plan("reading").via) == (0, "camera")
    assert (s.plan("command").answer, s.plan("command").via) == (3, "touch")  # its maximum
    for text, fragment in [
        ("test: mmse\npatient: A\nitems:\n  recall: {points: 4}\n", "not a score"),
        ("test: mmse\npatient: A\nitems:\n  recall: {points: 1, via: touch}\n", "via must be"),
        ("test: mmse\npatient: A\nitems:\n  feeding: {points: 1}\n", "unknown item 'feeding'"),
        ("test: mmse\npatient: A\nitems:\n  recall: {points: 1, answer: 1}\n", "give one"),
        ("test: moca\npatient: A\n", "test must be one of"),
    ]:
        with pytest.raises(ScenarioError, match=fragment):
            parse_scenario(text, "x.yaml")


def test_the_clinician_scores_a_drawing_until_the_result_is_validated(tmp_path):
    store = ResultsStore(tmp_path / "db.sqlite")
    result = Robot(test="mmse").run_test()
    test_id = store.store(result)
    with pytest.raises(InvalidResult, match="not scored by the clinician"):
        store.score(test_id, "recall", 1, "Dr. Ruiz")
    with pytest.raises(InvalidResult, match="one of"):
        store.score(test_id, "writing", 2, "Dr. Ruiz")
    after = store.score(test_id, "writing", 1, "Dr. Ruiz")
    assert after["total"] == 29 and after["complete"] is False
    after = store.score(test_id, "copying", 0, "Dr. Ruiz")
    assert (
        after["total"] == 29 and after["complete"] is True and after["band"] == "normal cognition"
    )
    writing = next(i for i in after["items"] if i["item"] == "writing")
    assert writing["scored_by"] == "Dr. Ruiz" and writing["points"] == 1
    store.validate(test_id, "Dr. Ruiz")
    with pytest.raises(InvalidResult, match="cannot change"):
        store.score(test_id, "copying", 1, "Dr. Ruiz")
    assert store.tests()[0]["total"] == 29
    assert store.patients()[0]["name"] == "Carlos" and store.tests()[0]["patient_id"] == 1


def test_the_clinician_scores_what_the_robot_could_not_understand(tmp_path):
    """An MMSE answer never understood is stored without points, with what was heard and its
    clips: the result is provisional, with no band, until the clinician scores it; every score
    is kept."""
    store = ResultsStore(tmp_path / "db.sqlite")
    result = Robot(Patient(answers={"recall": ["garbled", "garbled"]}), test="mmse").run_test()
    test_id = store.store(result)
    listed = store.test(test_id)
    recall = next(i for i in listed["items"] if i["item"] == "recall")
    assert recall["needs_clinician"] and recall["points"] is None and len(recall["audio"]) == 2
    assert listed["provisional"] and listed["band"] is None
    assert listed["total_range"] == [listed["total"], listed["total"] + 3]
    for item, points in (("writing", 1), ("copying", 1), ("recall", 2)):
        listed = store.score(test_id, item, points, "Dr. Ruiz")
    assert listed["provisional"] is False and listed["band"] == "normal cognition"
    assert listed["total"] == listed["total_range"][0] == listed["total_range"][1] == 29
    listed = store.score(test_id, "recall", 3, "Dr. Vega")  # a re-score keeps the first
    assert [(s["item"], s["points"]) for s in listed["scores"]][-2:] == [
        ("recall", 2),
        ("recall", 3),
    ]
    store.validate(test_id, "Dr. Vega")
    assert store.tests()[0]["total"] == 30


def comparable(result):
    """What a restart must not change (attempts may: the item in progress is asked again)."""
    items = {i["item"]: (i["points"], i["via"], i.get("drawing", "")) for i in result["items"]}
    return items, result["total"], result["unanswered"], result["complete"]


@pytest.mark.parametrize("moment", [1, 8, 30, 60, 90, 105, 118, 128, 138, 150])
@pytest.mark.parametrize("agent", ["pelea", "panel", "speech"])
def test_an_agent_killed_at_any_moment_of_an_mmse_gives_the_same_result(agent, moment):
    expected = Robot(test="mmse").run_test()
    robot = Robot(test="mmse")
    robot.bus.after(moment, getattr(robot, f"restart_{agent}"))
    result = robot.run_test()
    assert len(robot.port.stored) == 1
    assert comparable(result) == comparable(expected)
