"""Answers understood in Spanish (issue "Heard right, or asked again", part 5): the same rules
as in English read the Spanish words of clarc_agents/languages/es.yaml; numbers said in words
are made digits by text2num; the Spanish Barthel (definitions/es/barthel.yaml) is the English
one item for item and point for point."""

from dataclasses import replace
from datetime import date

import pytest

from clarc_agents import definitions, languages
from clarc_agents.exceptions import DefinitionError
from clarc_agents.questionnaire.answers import understand
from clarc_agents.questionnaire.orientation import values
from clarc_agents.questionnaire.spoken import words

TODAY = date(2025, 12, 1)  # a Monday, in winter
BARTHEL = definitions.load("barthel", "es")
ENGLISH_MMSE = definitions.load("mmse")
# the Mini-Mental's orientation and serial sevens, asked in Spanish (their parts are values,
# not English words: a date's placeholders, numbers)
ORIENTATION = replace(
    ENGLISH_MMSE.filled(values(TODAY, code="es")).item("orientation_time"), language="es"
)
SERIAL = replace(ENGLISH_MMSE.item("attention"), language="es")


@pytest.mark.parametrize(
    "text, expected",
    [
        ("Noventa y tres, ochenta y seis, setenta y nueve", ["93", "86", "79"]),
        ("Estamos en dos mil veintiséis", ["estamos", "en", "2026"]),
        ("la segunda opción", ["la", "2nd", "opcion"]),
        ("el primer piso", ["el", "1st", "piso"]),
        ("una manzana, un peso y una mesa", ["una", "manzana", "un", "peso", "y", "una", "mesa"]),
        ("treinta y una", ["31"]),
        ("tengo ochenta y un años", ["tengo", "81", "anos"]),
        ("¿Qué? No sé", ["que", "no", "se"]),
        ("Sí, otoño", ["si", "otono"]),
    ],
)
def test_spanish_words_and_numbers_however_said(text, expected):
    assert words(text, "es") == expected


@pytest.mark.parametrize("test", ["barthel", "lawton", "mmse"])
def test_a_spanish_test_is_the_english_one_item_for_item(test):
    english, spanish = definitions.load(test), definitions.load(test, "es")
    assert spanish.language == "es" and all(i.language == "es" for i in spanish.items)
    assert spanish.order == english.order and spanish.bands == english.bands
    for ours, theirs in zip(spanish.items, english.items, strict=True):
        assert ours.points == theirs.points and ours.kind == theirs.kind
        assert len(ours.parts) == len(theirs.parts)
        # each option as the simulated patient says it, and as it is written, is that option
        for option in ours.options:
            for said in (option.says, option.text):
                assert understand(ours, said).points == option.points, (ours.key, said)
    assert "Hola Ana" in spanish.sentence("greet", patient="Ana")


@pytest.mark.parametrize(
    "item, said, expected",
    [
        ("feeding", "No puedo comer yo solo", 0),  # "solo" denied
        ("feeding", "Como sola, sin ayuda", 10),
        ("feeding", "Necesito que me corten la carne", 5),
        ("feeding", "la segunda", 5),
        ("feeding", "la opción tres", 10),
        ("feeding", "tres", 10),
        ("feeding", "uno", 0),
        ("feeding", "la última", 10),
        ("feeding", "la segunda, no, la tercera", 10),
        ("bowels", "No, nunca las controlo", 0),
        ("bowels", "Sí", 10),
        ("bowels", "de vez en cuando tengo algún accidente", 5),
        ("stairs", "No, no puedo", 0),
        ("mobility", "Camino con un bastón", 15),
        ("mobility", "Voy en silla de ruedas", 5),
        ("transfers", "me tienen que ayudar dos personas", 5),
        ("dressing", "me ayudan con los botones", 5),
    ],
)
def test_the_barthel_answered_in_spanish_as_people_say_it(item, said, expected):
    assert understand(BARTHEL.item(item), said).points == expected, said


LAWTON = definitions.load("lawton", "es")


@pytest.mark.parametrize(
    "item, said, expected",
    [
        ("telephone", "No, no lo uso", 0),  # "lo uso" denied
        ("telephone", "Sí, llamo a mi hija todos los días", 1),
        ("food_preparation", "Nunca cocino, me cocina mi hija", 0),
        ("food_preparation", "Cocino yo sola", 1),
        ("finances", "Mi hija lleva mi dinero", 0),
        ("finances", "Me encargo yo", 1),
        ("transportation", "Cojo el autobús", 1),
        ("transportation", "la primera", 0),
        ("medication", "No", None),  # a bare no is no option of this item
    ],
)
def test_the_lawton_answered_in_spanish_as_people_say_it(item, said, expected):
    assert understand(LAWTON.item(item), said).points == expected, said


@pytest.mark.parametrize(
    "said", ["No sé", "No me acuerdo", "Ni idea", "mmm, pues", "no la segunda"]
)
def test_not_knowing_mumbling_or_a_denied_option_chooses_nothing(said):
    assert understand(BARTHEL.item("feeding"), said).kind == "not_understood"


def test_the_simulated_patient_s_mumble_is_no_answer_in_spanish():
    from clarc_sim.patient.script import GARBLED

    assert understand(SERIAL, GARBLED["es"]).kind == "not_understood"
    assert understand(BARTHEL.item("feeding"), GARBLED["es"]).kind == "not_understood"


def test_asking_to_skip_in_spanish():
    assert understand(BARTHEL.item("stairs"), "siguiente pregunta").kind == "skip"


@pytest.mark.parametrize(
    "said, expected",
    [
        ("Estamos en invierno, es lunes uno de diciembre de dos mil veinticinco", 5),
        ("dos mil veinticinco, invierno, día uno, lunes, diciembre", 5),
        ("martes, no, lunes, diciembre", 2),  # taken back: Monday counts
        ("lunes o martes, diciembre", 1),  # hedged: no point for the weekday
        ("noviembre, diciembre", 0),  # the month said among rivals
    ],
)
def test_orientation_in_time_said_in_spanish(said, expected):
    assert understand(ORIENTATION, said).points == expected, said


@pytest.mark.parametrize(
    "said, expected",
    [
        ("noventa y tres, ochenta y seis, setenta y nueve, setenta y dos, sesenta y cinco", 5),
        ("cien menos siete, noventa y tres; menos siete, ochenta y cinco", 1),
        ("noventa y tres, ochenta y cinco, setenta y ocho", 2),
    ],
)
def test_the_serial_sevens_said_in_spanish(said, expected):
    assert understand(SERIAL, said).points == expected, said


MMSE = definitions.load("mmse", "es").filled(values(date(2026, 12, 6), code="es"))  # a Sunday


@pytest.mark.parametrize(
    "item, said, expected",
    [
        ("orientation_time", "dos mil veintiséis, invierno, seis, domingo, diciembre", 5),
        ("orientation_time", "estamos a seis de diciembre de dos mil veintiséis, domingo", 4),
        ("orientation_place", "España, Andalucía, Sevilla, el Virgen del Rocío, primera planta", 5),
        ("orientation_place", "Spain, Seville, en el primer piso", 3),  # the English names too
        ("registration", "manzana, bicicleta y cuchara", 3),
        ("recall", "una cuchara y una mesa", 1),
        (
            "attention",
            "noventa y tres, ochenta y seis, setenta y nueve, setenta y dos, sesenta y cinco",
            5,
        ),
        ("attention", "cien menos siete noventa y tres, menos siete ochenta y seis", 2),
        ("naming", "un lápiz y un reloj", 2),
        ("naming", "un bolígrafo y un reloj de pulsera", 1),
        ("repetition", "Ni sí, ni no, ni pero", 1),
        ("repetition", "ni sí ni no", 0),
    ],
)
def test_the_mini_mental_answered_in_spanish_as_people_say_it(item, said, expected):
    assert understand(MMSE.item(item), said).points == expected, said


def test_the_simulated_patient_earns_each_score_in_spanish():
    from clarc_sim.patient.answering import words_for

    for item in MMSE.items:
        for points in range(item.max + 1) if item.kind in ("words", "serial") else ():
            said = words_for(item, points)
            assert understand(item, said).points == points, (item.key, said)
    assert words_for(MMSE.item("recall"), 0) == "No lo sé"


def test_a_language_that_is_not_shipped_is_named(tmp_path, monkeypatch):
    with pytest.raises(DefinitionError, match="no language 'xx'"):
        languages.get("xx")
    english = definitions.path_of("barthel").read_text(encoding="utf-8")
    bad = english.replace("test: barthel", "test: barthel\nlanguage: xx", 1)
    with pytest.raises(DefinitionError, match=r"barthel\.yaml:\d+: no language 'xx'"):
        definitions.parse(bad, "barthel.yaml")
    with pytest.raises(DefinitionError, match=r"no language 'fr' \(there are: en, es\)"):
        definitions.load("barthel", "fr")
    shipped = definitions.path_of

    def hidden(test, language="en"):  # as if the Spanish Mini-Mental were not shipped
        return (
            tmp_path / "none.yaml"
            if (test, language) == ("mmse", "es")
            else shipped(test, language)
        )

    monkeypatch.setattr(definitions, "path_of", hidden)
    with pytest.raises(DefinitionError, match=r"'mmse' in 'es' \(it is shipped in: en\)"):
        definitions.load.__wrapped__("mmse", "es")  # not the cached one


def test_a_language_file_is_read_strictly():
    source = languages.path_of("es").read_text(encoding="utf-8")
    assert languages.parse(source, "es.yaml").weekdays[0] == "lunes"
    with pytest.raises(DefinitionError, match=r"es\.yaml:\d+: weekdays lists 7, got 6"):
        languages.parse(source.replace("lunes, ", "", 1), "es.yaml")
    with pytest.raises(DefinitionError, match="each is a text"):
        languages.parse(source.replace('"tampoco"', "no", 1), "es.yaml")  # YAML's no: a bool
    with pytest.raises(DefinitionError, match="missing"):
        languages.parse(source.replace("hedges: [o, u]\n", ""), "es.yaml")


def test_clarc_understand_in_spanish(capsys):
    import json

    from clarc_sim.console import clarc_cli

    def run(*args):
        code = clarc_cli.main(["understand", *args])
        out, err = capsys.readouterr()
        return code, out, err

    code, out, _ = run("barthel", "feeding", "la segunda opción", "--language", "es", "--json")
    doc = json.loads(out)
    assert code == 0 and doc["points"] == 5 and doc["language"] == "es", doc
    code, out, _ = run("barthel", "feeding", "No puedo comer yo solo", "--language", "es")
    assert code == 0 and out.startswith("barthel feeding (choose): answer, 0 of 10 points")
    code, out, _ = run("mmse", "registration", "manzana y cuchara", "--language", "es")
    assert code == 0 and out.startswith("mmse registration (words): answer, 2 of 3 points")
    code, _, err = run("lawton", "telephone", "uno", "--language", "fr")
    assert code == 1 and "no language 'fr'" in err
    mine = definitions.path_of("barthel", "es")
    code, _, err = run(str(mine), "feeding", "uno", "--language", "en")
    assert code == 1 and "is in 'es', not 'en'" in err


def test_a_whole_barthel_asked_and_answered_in_spanish():
    """The robot asks in Spanish and understands Spanish answers through Speech's and Panel's
    rules (the items' language in the DSR), the read-back confirmed with a Spanish yes; the
    result is the one the same answers give in English."""
    from local_clarc import Patient, Robot

    answers = {
        "bathing": [("touch", 0)],
        "dressing": ["garbled", ("voice", 5)],
        "bowels": ["silence", ("voice", 10)],
        "transfers": [("unsure", 10)],
    }
    spanish = Robot(Patient(answers=dict(answers), confirms=["yes"]), language="es")
    result = spanish.run_test("Carmen")
    english = Robot(Patient(answers=dict(answers), confirms=["yes"])).run_test("Carmen")
    got = {i["item"]: (i["points"], i["via"]) for i in result["items"]}
    assert got == {i["item"]: (i["points"], i["via"]) for i in english["items"]}
    assert result["total"] == english["total"] == 85 and got["transfers"] == (10, "voice")
    said = " ".join(spanish.said)
    assert "Pregunta 1 de 10, Comer. ¿Puede comer usted solo?" in said
    assert "He entendido: Necesito un poco de ayuda. ¿Es correcto?" in said
    assert "Perdone, no le he entendido." in said and "Question" not in said
    graph = spanish.pelea_link.graph
    assert graph.node("item_feeding").attrs["language"] == "es"
    assert graph.node("test").attrs["language"] == "es"


def test_a_whole_lawton_asked_and_answered_in_spanish():
    from local_clarc import Patient, Robot

    answers = {
        "shopping": [("voice", 0)],
        "transportation": [("touch", 0)],
        "laundry": ["garbled", ("voice", 1)],
    }

    def run(language):
        robot = Robot(Patient(answers=dict(answers)), test="lawton", language=language)
        return robot, robot.run_test("Elena")

    spanish, result = run("es")
    _, english = run("en")
    got = {i["item"]: (i["points"], i["via"]) for i in result["items"]}
    assert got == {i["item"]: (i["points"], i["via"]) for i in english["items"]}
    assert result["total"] == english["total"] == 6 and result["band"] == "mostly independent"
    said = " ".join(spanish.said)
    assert "Pregunta 1 de 8, Usar el teléfono." in said and "Question" not in said


def test_a_whole_mini_mental_asked_and_answered_in_spanish():
    """Orientation against today said in Spanish and the default place's Spanish names, the
    Spanish words to remember, the serial sevens in Spanish numbers: the English result."""
    from local_clarc import Patient, Robot

    answers = {
        "orientation_place": [("voice", 3)],
        "recall": [("voice", 2)],
        "attention": ["garbled", ("voice", 4)],
        "naming": ["silence", ("voice", 2)],
    }

    def run(language):
        robot = Robot(Patient(answers=dict(answers)), test="mmse", language=language)
        return robot, robot.run_test("Ana")

    spanish, result = run("es")
    _, english = run("en")
    got = {i["item"]: (i["points"], i["via"], i["attempts"]) for i in result["items"]}
    assert got == {i["item"]: (i["points"], i["via"], i["attempts"]) for i in english["items"]}
    assert got["orientation_time"][0] == 5 and got["attention"] == (4, "voice", 2)
    said = " ".join(spanish.said)
    assert "bicicleta, cuchara, manzana" in said and "apple" not in said


def test_a_start_asks_for_the_language_and_one_not_shipped_is_not_taken():
    """The Start request names the language (requested_language): PELEA takes it in Spanish,
    and leaves a Start for a language the test is not shipped in."""
    from clarc_agents.test_node import request_start

    from local_clarc import Robot

    robot = Robot()
    clinician = robot.bus.agent("/clarc_start")
    clinician.send(request_start("Ana", "t1", "barthel", language="fr"))
    robot.bus.run(until=lambda: False, limit=5.0)
    assert not robot.hle.running and robot.said == []
    clinician.send(request_start("Ana", "t2", "barthel", language="es"))
    robot.bus.run(until=lambda: bool(robot.said), limit=30.0)
    assert robot.hle.running and robot.hle.definition.language == "es"
    assert robot.said[0].startswith("Hola Ana, soy CLARC.")


def test_after_a_test_in_spanish_a_start_naming_no_language_is_in_english():
    from local_clarc import Robot

    robot = Robot()
    graph = robot.pelea_link.graph
    robot.hle._in_language("es")
    assert robot.hle.template.language == "es"
    robot.hle._in_language("xx")  # not shipped: stays as it was, saying so
    assert robot.hle.template.language == "es"
    robot.hle._begin(graph, "Ana")  # no requested_language on the test node
    assert robot.hle.definition.language == "en"


def test_a_scenario_in_spanish_is_said_in_a_spanish_voice_unless_it_names_one():
    from clarc_sim.patient.scenario import load, parse, voice_for

    assert load("scenarios/barthel_es.yaml").voice == ("es", 150, 50)
    assert load("scenarios/default.yaml").voice == ("en-us", 150, 50)
    named = parse("language: es\npatient: Carmen\nvoice: {name: es-419, rate: 130}\n")
    assert named.voice == ("es-419", 130, 50)
    assert (voice_for("es"), voice_for("en")) == ("es", "en-us")  # the robot's, launch.sh's too
