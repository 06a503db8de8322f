"""What CLARC says and shows at each step of a questionnaire test (pure), from its definition.
Each sentence says whether it needs the patient in front of the robot (speech stops and the
screen clears if they leave), which options, if any, the touch screen shows with it, what else
it shows (pictures, targets, a written instruction) and what it takes from the patient
(``input``: options, targets, drawing, or nothing). The robot's own words are the test's
language's (clarc_agents/languages/<code>.yaml, ``sentences``)."""

from __future__ import annotations

from clarc_agents import languages
from clarc_agents.definitions import Definition, Item
from clarc_agents.sentence import Sentence

_ENGLISH = languages.get("en")
ASK = _ENGLISH.say("ask")
AGAIN = _ENGLISH.say("again")  # also the Get Up & Go's, which is asked in English
# what the screen takes from the patient while an item of each kind is asked
INPUTS = {"choose": "options", "words": "", "touches": "targets", "drawing": "drawing"}
INPUTS |= {"eyes": "", "serial": ""}


def greet(definition: Definition, patient: str) -> Sentence:
    return Sentence(definition.sentence("greet", patient=patient))


def explain(definition: Definition) -> Sentence:
    return Sentence(definition.sentence("explain"))


def _said_in(definition: Definition | None) -> languages.Language:
    """The definition's language (English for a sentence of no test's)."""
    return _ENGLISH if definition is None else languages.get(definition.language)


def introduce(definition: Definition, key: str) -> Sentence:
    item = definition.item(key)
    position = definition.order.index(key) + 1
    count, title, question = len(definition.items), item.title, item.question
    return Sentence(
        _said_in(definition).say(
            "introduce", position=position, count=count, title=title, question=question
        ),
        item=key,
        shows=list(item.shows) if item.kind == "words" else [],
    )


def _answering(text: str, item: Item) -> Sentence:
    """A sentence that asks for the answer: the screen shows what the item needs."""
    if item.kind == "choose":
        return Sentence(
            text,
            item=item.key,
            options=[o.text for o in item.options],
            option_points=[float(o.points) for o in item.options],
            input="options",
        )
    return Sentence(text, item=item.key, shows=list(item.shows), input=INPUTS[item.kind])


def _spoken_options(said_in: languages.Language, item: Item) -> str:
    return " ".join(
        said_in.say("option", number=i + 1, text=o.text) for i, o in enumerate(item.options)
    )


def describe_options(definition: Definition, key: str) -> Sentence:
    item, said_in = definition.item(key), _said_in(definition)
    return _answering(f"{said_in.say('options_are')} {_spoken_options(said_in, item)}", item)


def ask(definition: Definition, key: str) -> Sentence:
    item = definition.item(key)
    return _answering(_said_in(definition).say("ask") if item.kind == "choose" else item.ask, item)


def options_again(definition: Definition, key: str) -> Sentence:
    """No answer in time: the options again by voice, all of them on the screen (or, for an
    item without options, the question and the request again)."""
    item, said_in = definition.item(key), _said_in(definition)
    if item.kind != "choose":
        return _answering(f"{said_in.say('ask_again')} {item.question} {item.ask}", item)
    options = _spoken_options(said_in, item)
    return _answering(f"{said_in.say('again')} {options} {said_in.say('touch_too')}", item)


def clarify(definition: Definition, key: str) -> Sentence:
    """Not understood: repeat, offer the touch screen (if the item has options), offer to
    skip."""
    item, said_in = definition.item(key), _said_in(definition)
    sorry = said_in.say("clarify")
    if item.kind != "choose":
        return _answering(f"{sorry} {item.ask} {said_in.say('clarify_words')}", item)
    return _answering(f"{sorry} {item.question} {said_in.say('clarify_choose')}", item)


def sit_down(definition: Definition | None = None) -> Sentence:
    return Sentence(_said_in(definition).say("sit_down"), needs_person=False)


def call_clinician(definition: Definition | None = None) -> Sentence:
    return Sentence(_said_in(definition).say("call_clinician"))


def goodbye(definition: Definition, patient: str) -> Sentence:
    return Sentence(definition.sentence("goodbye", patient=patient), needs_person=False)
