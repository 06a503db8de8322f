"""Answers understood as people say them (questionnaire/spoken.py, questionnaire/answers.py;
docs/FORMAT.md "How answers are understood"): case and punctuation never matter; numbers in
words or digits, ordinals and years; an option chosen by number or position; a hedged answer
gets no credit for that part, nor does a value said among rivals of its kind, but a value taken
back ("Tuesday, no, Monday") is replaced by the one after it; the narrated
serial sevens are scored on the numbers given as answers; the three-stage command scores each
stage done in order; "I don't know" and fillers are never an option."""

from datetime import date

import pytest

from clarc_agents import definitions
from clarc_agents.questionnaire.answers import touched_in_order, understand
from clarc_agents.questionnaire.orientation import values
from clarc_agents.questionnaire.spoken import words

TODAY = date(2025, 12, 1)  # a Monday, in winter
MMSE = definitions.load("mmse").filled(values(TODAY))
LAWTON = definitions.load("lawton")
BARTHEL = definitions.load("barthel")


def points(item_key: str, text: str, test=MMSE):
    return understand(test.item(item_key), text).points


@pytest.mark.parametrize(
    "text, expected",
    [
        ("No ifs, ands, or buts.", ["no", "ifs", "ands", "or", "buts"]),
        ("NO IFS ANDS OR BUTS", ["no", "ifs", "ands", "or", "buts"]),
        ("ninety-three", ["93"]),
        ("one hundred minus seven", ["100", "minus", "7"]),
        ("a hundred and five", ["105"]),
        ("twenty twenty five", ["2025"]),
        ("two thousand and twenty-five", ["2025"]),
        ("two thousand twenty five", ["2025"]),
        ("2000 and 26 winter", ["2026", "winter"]),  # as Whisper writes the year
        ("2000, and 26", ["2000", "and", "26"]),  # a pause: two numbers
        ("nineteen ninety-nine", ["1999"]),
        ("twenty oh five", ["2005"]),
        ("twenty, twenty five", ["20", "25"]),  # a pause: two numbers
        ("two thousand um twenty six", ["2026"]),  # a hesitation inside a number: still one
        ("twenty uh uh twenty five", ["2025"]),
        ("ninety three um eighty six", ["93", "86"]),
        ("um twenty six um", ["um", "26", "um"]),  # around a number: left to the scoring
        ("two thousand, um, twenty six", ["2000", "um", "26"]),  # a pause still ends it
        ("ninety three eighty six", ["93", "86"]),  # not a year
        ("the first of December", ["the", "1st", "of", "december"]),
        ("the twenty-first", ["the", "21st"]),
        ("the thirtieth", ["the", "30th"]),
        ("1st December", ["1st", "december"]),
        ("I don\u2019t know", ["i", "don't", "know"]),
    ],
)
def test_words_and_numbers_however_said(text, expected):
    assert words(text) == expected


@pytest.mark.parametrize(
    "said",
    [
        "No ifs, ands, or buts.",
        "no ifs ands or buts",
        "No ifs, ands or buts!",
        "no-ifs, ands, or buts",
        "NO IFS, ANDS, OR BUTS",
    ],
)
def test_repetition_ignores_case_and_punctuation(said):
    assert points("repetition", said) == 1


@pytest.mark.parametrize(
    "said, expected",
    [
        ("Monday, the first of December, twenty twenty five, winter", 5),
        ("It's Monday the 1st of December 2025, in winter", 5),
        ("December the first, two thousand and twenty five, a Monday in winter", 5),
        ("twenty twenty-five, winter, 1 December, Monday", 5),
        ("Monday or Tuesday, December, 2025, winter, the first", 4),  # a hedged weekday
        ("Tuesday or Monday, December 2025, winter, the first", 4),
        ("2024 or 2025, winter, the first, Monday, December", 4),  # a hedged year
        ("Monday Tuesday Wednesday Thursday Friday Saturday Sunday", 0),  # every weekday
        (
            "2024 2025 spring summer autumn winter the first the second Monday Tuesday "
            "January February December",
            0,
        ),
        ("the second of December, 2025, winter, Monday", 4),  # the date wrong
        ("I don't know", 0),  # an answer, worth nothing
    ],
)
def test_orientation_in_time_as_people_say_the_date(said, expected):
    assert points("orientation_time", said) == expected


@pytest.mark.parametrize(
    "item, said, expected",
    [
        ("orientation_time", "Tuesday, no, Monday, the first of December, 2025, winter", 5),
        ("orientation_time", "Monday, sorry, Tuesday, the first of December, 2025, winter", 4),
        ("orientation_time", "the second, I mean the first, December, 2025, winter, Monday", 5),
        ("orientation_time", "twenty twenty four, no wait, twenty twenty five, winter", 2),
        ("orientation_time", "autumn, no, I mean, winter, December", 2),
        ("orientation_time", "Monday, no, December", 2),  # not a value of the same kind
        ("attention", "93, 86, 78, no, 79, 72, 65", 5),
        ("attention", "93, 86, 79, 72, no, 65", 5),  # a "no" of hesitation: 65 is the next
        ("attention", "93, 86, 79, no, 72, 65", 5),
        ("attention", "ninety three, eighty six, seventy nine, sorry, eighty, 73", 3),
        ("repetition", "No ifs, ands, or buts", 1),  # a "no" that takes nothing back
    ],
)
def test_a_value_taken_back_is_replaced_by_the_one_said_after_it(item, said, expected):
    assert points(item, said) == expected


def test_what_a_hedge_costs_is_named():
    meaning = understand(MMSE.item("orientation_time"), "Monday or Tuesday, winter")
    assert meaning.points == 1 and meaning.matched == ("winter",)
    assert any("monday" in w and "hedged" in w for w in meaning.why), meaning.why


@pytest.mark.parametrize(
    "said, expected",
    [
        ("a pencil and a watch", 2),
        ("a pen or a pencil, and a watch", 1),  # hedged: no point for the pencil
        ("pencil... or a pen? and a clock", 1),
        ("a watch or a clock", 0),  # either side of an "or"
    ],
)
def test_naming_gives_no_credit_for_a_hedged_name(said, expected):
    assert points("naming", said) == expected


@pytest.mark.parametrize(
    "said, expected",
    [
        (
            "one hundred minus seven is ninety three, minus seven eighty six, minus seven "
            "seventy nine, minus seven seventy two, minus seven sixty five",
            5,
        ),
        ("100 take away 7 is 93, take away 7 is 86, 79, 72, 65", 5),
        # each subtraction said whole: the number it starts from restates the last answer
        (
            "100 minus 7 is 93, 93 minus 7 is 86, 86 minus 7 is 79, 79 minus 7 is 72, "
            "72 minus 7 is 65",
            5,
        ),
        ("93 minus 7 is 85, 85 minus 7 is 78", 2),
        ("93, 85 minus 7 is 78", 2),  # 85 was not said before: it is an answer
        ("93, 86, 86, 79", 3),  # 86 said again is an answer (wrong), 79 then right
        ("a hundred less seven, ninety-three; less seven, eighty-five", 1),
        ("ninety three eighty six seventy nine seventy two sixty five", 5),
        ("93. 86. 79. 72. 65.", 5),
        ("ninety-three, eighty-five, seventy-eight", 2),
    ],
)
def test_narrated_serial_sevens_are_scored_on_the_answers_given(said, expected):
    assert points("attention", said) == expected


@pytest.mark.parametrize(
    "said",
    ["I don't know", "I do not know", "Dunno", "not sure", "I can't remember", "Hmm, no idea"],
)
def test_not_knowing_is_never_an_option(said):
    for item in LAWTON.items:
        assert understand(item, said).kind == "not_understood", (item.key, said)


@pytest.mark.parametrize(
    "item, said, expected",
    [
        ("laundry", "No, someone else does it", 0),  # "no" answers, denies nothing
        ("laundry", "I can't, someone else does it", 0),
        ("telephone", "I can't do it myself", None),  # not "myself" (1)
        ("telephone", "No, I never use it", 0),
        ("telephone", "I can't use the phone myself", None),  # four words back: still denied
        ("transportation", "I don't drive but I take the bus", 1),  # "but" ends the denial
        ("medication", "I take them myself, no problem", 1),
        ("housekeeping", "I do not do any housework", 0),
        ("food_preparation", "I don't cook, my daughter cooks for me", 0),
    ],
)
def test_the_lawton_answered_with_denials(item, said, expected):
    assert understand(LAWTON.item(item), said).points == expected


@pytest.mark.parametrize(
    "said, position",
    [
        ("two", 2),
        ("2", 2),
        ("option two", 2),
        ("Option 2.", 2),
        ("number two", 2),
        ("the second one", 2),
        ("the second", 2),
        ("The first one, please", 1),
        ("one", 1),
        ("the last one", 3),
        ("The last option.", 3),
    ],
)
def test_an_option_chosen_by_number_or_position(said, position):
    item = BARTHEL.item("feeding")
    assert understand(item, said).points == item.options[position - 1].points


@pytest.mark.parametrize(
    "item, said, expected",
    [
        ("bowels", "no problems", 10),  # "no problems" is one keyword, not the "no" of 0
        ("bowels", "I never have accidents", 10),
        ("bowels", "I have accidents now and then", 5),
        ("bladder", "no, I do not control it", 0),
        ("feeding", "I feed myself", 10),
        ("feeding", "someone has to cut my meat", 5),
        ("feeding", "they have to feed me", 0),
        ("bathing", "I can wash myself in the shower", 5),
        ("bathing", "my daughter helps me bathe", 0),
        ("dressing", "I need help with buttons but do the rest", 5),
        ("dressing", "I can dress myself", 10),
        ("transfers", "I need a lot of help", 5),
        ("mobility", "I walk with a stick on my own", 15),
        ("mobility", "I need someone to walk with me", 10),
        ("stairs", "I need someone to help me on the stairs", 5),
        # a keyword denied where it is said is no hit (negation within the clause)
        ("feeding", "I can't eat by myself", 0),
        ("feeding", "I cannot eat on my own", 0),
        ("bathing", "I can't bathe by myself", 0),
        ("bathing", "No, I need help", 0),  # the "no" answers; "need help" is not denied
        ("bathing", "Nobody helps me so I wash myself", 5),  # denied: "helps me" only
        # no comma reaches the rules (a recogniser writes none): "nobody" reaches "wash myself"
        # too, and the answer is asked again rather than scored
        ("bathing", "Nobody helps me, I wash myself", None),
        ("grooming", "no I can't", 0),
        ("mobility", "I am not independent", None),
        ("bowels", "not always", None),  # not "always" (10): asked again
        ("bowels", "I don't have accidents", None),  # not "accidents" (5): asked again
        ("grooming", "I don't need help", None),  # not "need help" (0): asked again
        # what the instrument leaves to the examiner stays not understood: asked again
        ("bladder", "I wear a catheter", None),
        ("mobility", "I walk with a stick and someone helps me", None),
    ],
)
def test_the_barthel_answered_as_people_say_it(item, said, expected):
    assert points(item, said, BARTHEL) == expected


@pytest.mark.parametrize(
    "item, said, expected",
    [
        ("telephone", "I call my daughter every day", 1),
        ("telephone", "I can answer it but not dial", 1),  # Lawton & Brody: answers, 1
        ("shopping", "I go shopping on my own", 1),
        ("shopping", "my son does my shopping", 0),
        ("shopping", "I only buy small things on my own", None),  # small purchases: 0, or 1?
        ("food_preparation", "I don't cook, my wife does", 0),
        ("transportation", "I drive", 1),
        ("transportation", "no, my son drives me", 0),
        ("medication", "I take my pills myself", 1),
        ("medication", "my wife gives me my pills", 0),
        ("medication", "I take them myself if someone prepares them", None),
        ("finances", "my son handles my money", 0),
        ("finances", "I don't handle money", 0),
        ("finances", "I manage my own money", 1),
    ],
)
def test_the_lawton_answered_as_people_say_it(item, said, expected):
    assert points(item, said, LAWTON) == expected


def test_an_option_number_that_does_not_exist_is_not_understood():
    meaning = understand(LAWTON.item("telephone"), "option four")
    assert meaning.kind == "not_understood" and "no option 4" in meaning.why[0]


@pytest.mark.parametrize(
    "touched, expected",
    [
        (["circle", "square", "triangle"], 3),
        (["circle", "square"], 2),  # then stopped
        (["square", "triangle", "star"], 2),  # two stages in order
        (["triangle", "circle", "square"], 2),
        (["triangle", "square", "circle"], 1),
        (["star", "star", "star"], 0),
        ([], 0),
    ],
)
def test_the_three_stage_command_scores_each_stage_done_in_order(touched, expected):
    assert touched_in_order(MMSE.item("command"), touched) == expected


def test_eyes_closed_are_an_answer_after_a_second_and_a_blink_never():
    from clarc_agents.behaviours.closed_eyes import ClosedEyes

    eyes = ClosedEyes(scale=0.1)  # a tenth of the patient's time: 0.1 s is a second
    blink = [eyes.see(closed, 10.0 + 0.01 * k) for k, closed in enumerate([1, 1, 1, 1, 0])]
    assert blink == [False] * 5  # 0.3 s closed, then open
    held = [eyes.see(True, 11.0 + 0.02 * k) for k in range(7)]
    assert held == [False] * 5 + [True, True]  # closed from 11.00: a second at 11.10
    assert not eyes.see(False, 11.2) and not eyes.see(True, 11.21)  # opened: counted again


def run_understand(capsys, *argv):
    from clarc_sim.console.clarc_cli import main

    code = main(["understand", *argv])
    out = capsys.readouterr()
    return code, out.out, out.err


def test_clarc_understand_prints_the_points_and_why(capsys):
    import json

    code, out, _ = run_understand(
        capsys,
        "mmse",
        "orientation_time",
        "Monday or Tuesday, the 1st, 2025",
        "--json",
        "--date",
        "2025-12-01",
    )
    doc = json.loads(out)
    assert code == 0 and doc["points"] == 2 and doc["max"] == 5 and doc["understood"] == "answer"
    assert doc["text"] == "Monday or Tuesday, the 1st, 2025" and "hedged" in doc["why"][0]
    code, out, _ = run_understand(capsys, "lawton", "telephone", "I don't know", "--json")
    assert code == 0 and json.loads(out)["points"] is None
    code, out, _ = run_understand(capsys, "mmse", "command", "circle, square", "--json")
    assert json.loads(out)["points"] == 2
    code, out, _ = run_understand(capsys, "mmse", "repetition", "No ifs, ands, or buts.")
    assert code == 0 and out.startswith("mmse repetition (words): answer, 1 of 1 points")


def test_clarc_understand_reads_a_definition_file_and_names_what_is_wrong(capsys, tmp_path):
    mine = tmp_path / "mine.yaml"
    mine.write_text(definitions.path_of("lawton").read_text().replace("test: lawton", "test: mine"))
    code, out, _ = run_understand(capsys, str(mine), "telephone", "option two", "--json")
    assert code == 0 and '"test": "mine"' in out and '"points": 1' in out
    code, _, err = run_understand(capsys, "mmse", "nope", "x")
    assert code == 1 and "no item 'nope'" in err and "orientation_time" in err
    code, _, err = run_understand(capsys, "mmse", "reading", "x")
    assert code == 1 and "answered by the camera" in err
    code, _, err = run_understand(capsys, "nosuch", "x", "y")
    assert code == 1 and "neither a shipped test" in err


@pytest.mark.parametrize(
    "said, expected",
    [
        ("Spain, Andalusia, Seville, the Virgen del Rocío hospital, the first floor", 5),
        ("Spain? Andalusia, Seville, Virgen del Rocío, floor one", 5),  # accents never matter
        ("spain andalusia seville virgen del rocio the first", 5),  # the floor's ordinal alone
        ("Spain, Andalusia, Seville, Virgen del Rocio, the second floor", 4),
    ],
)
def test_the_place_said_with_accents_or_the_floor_as_a_number(said, expected):
    assert points("orientation_place", said) == expected


@pytest.mark.parametrize(
    "text", ["M-M-H, N-A, B-R-R.", "mmh... the, eh... brr", "uh, m, um", "H. M. M."]
)
def test_a_mumble_a_recogniser_spelt_out_is_no_answer(text):
    """Whisper writes a mumble as letters: to a words or serial item that is no answer worth 0
    (it is asked again), nor an option."""
    for key in ("orientation_time", "recall", "attention"):
        assert understand(MMSE.item(key), text).kind == "not_understood", (key, text)
    assert understand(BARTHEL.item("feeding"), text).kind == "not_understood"
    assert points("recall", "a penny") == 1  # a word with its article is still an answer


def test_tens_in_digits_and_a_unit_in_words_are_one_number():
    assert words("93, 80 seven, 80.") == ["93", "87", "80"]
    assert words("80, 7") == ["80", "7"]  # a pause: two numbers
    assert points("attention", "93, 80 six, 79") == 3


@pytest.mark.parametrize(
    "said, expected",
    [
        ("90, three.", 1),  # "ninety... three"
        ("93, 80, 7, 80.", 2),  # 93, 87, 80
        ("93, 86, 80, 70, 3.", 3),  # 93, 86, 80, 73
        ("93, 86, 79, 70, 2, 65", 5),
        ("93, 86, 80, 73", 3),  # a round tens followed by a two-digit answer stays itself
    ],
)
def test_a_unit_after_a_round_tens_finishes_it_in_the_serial_sevens(said, expected):
    """Whisper writes a pause inside "ninety three" as "90, 3": a unit alone is no serial
    answer, so it is the tens' unit; elsewhere a pause still ends a number."""
    assert points("attention", said) == expected
