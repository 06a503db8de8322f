"""Test definitions as data files (clarc_agents/definitions): the Barthel test is read from its
file, and a file with a mistake is refused naming the line."""

import pytest
from barthel_items import BY_KEY, DEFINITION, ORDER, band

from clarc_agents.definitions import load, parse
from clarc_agents.exceptions import DefinitionError
from clarc_agents.questionnaire import sentences

SMALL = """format: clarc-test
version: 1
test: small
title: A small test
scoring: sum
sentences:
  greet: "Hello {patient}."
  explain: "Two questions."
  goodbye: "Bye {patient}."
bands:
  - {name: low, min: 0, max: 1}
  - {name: high, min: 2, max: 2}
items:
  - key: phone
    title: Telephone
    question: Can you use the telephone?
    options:
      - {points: 0, text: "No", says: "No, I cannot", words: ["cannot", "no"]}
      - {points: 1, text: "Yes", says: "Yes, I can", words: ["yes", "i can"]}
  - key: shopping
    title: Shopping
    question: Can you do your shopping?
    options:
      - {points: 0, text: "No", says: "No", words: ["no"]}
      - {points: 1, text: "Yes", says: "Yes", words: ["Yes"]}
"""


def test_the_barthel_test_is_its_definition_file():
    definition = load("barthel")
    assert definition.test == "barthel" and [i.key for i in definition.items] == list(ORDER)
    assert definition.max_total == 100 and BY_KEY["transfers"].points == (0, 5, 10, 15)
    assert [band(t) for t in (0, 20, 21, 60, 61, 90, 91, 99, 100)] == [
        "total",
        "total",
        "severe",
        "severe",
        "moderate",
        "moderate",
        "slight",
        "slight",
        "independent",
    ]
    assert sentences.greet(DEFINITION, "Carlos").text.startswith("Hello Carlos, I am CLARC.")
    assert BY_KEY["bowels"].option(10).keywords[:3] == ("yes", "always", "i control")


def test_a_small_definition_reads():
    small = parse(SMALL, "small.yaml")
    assert [i.key for i in small.items] == ["phone", "shopping"] and small.max_total == 2
    assert small.band(1) == "low" and small.sentence("goodbye", patient="Ana") == "Bye Ana."
    assert small.items[1].option(1).keywords == ("yes",)  # lower case


YES = '{points: 1, text: "Yes", says: "Yes", words: ["Yes"]}'


@pytest.mark.parametrize(
    "change, error",
    [
        (("title: A small test", "titel: A small test"), ":4: unknown key 'titel'"),
        (("  - key: shopping", "  - key: phone"), ":20: item 'phone' is listed twice"),
        ((YES, YES.replace("points: 1", "points: 0")), ":25: shopping: two options worth 0"),
        (("max: 1}", "max: 0}"), ":12: band 'high': bands cover 0 to 2"),
        (("high, min: 2, max: 2", "high, min: 2, max: 3"), "bands end at 3, the items' total"),
        (('words: ["no"]', "words: []"), ":24: shopping: words is a list of phrases"),
        (("scoring: sum", "scoring: average"), ":5: scoring: sum is the one"),
        (('  goodbye: "Bye {patient}."\n', ""), ":7: sentences: missing goodbye"),
        (("version: 1", "version: [1"), "not valid YAML"),
    ],
)
def test_a_mistake_is_refused_naming_the_line(change, error):
    text = SMALL.replace(*change, 1)
    assert text != SMALL
    with pytest.raises(DefinitionError, match=error):
        parse(text, "small.yaml")
