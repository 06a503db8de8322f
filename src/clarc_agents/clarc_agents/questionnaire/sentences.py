"""What CLARC says and shows at each step of a questionnaire test (pure), from its definition.
Each sentence says whether it needs the patient in front of the robot (speech stops and the
screen clears if they leave), which options, if any, the touch screen shows with it, what else
it shows (pictures, targets, a written instruction) and what it takes from the patient
(``input``: options, targets, drawing, or nothing)."""

from __future__ import annotations

from clarc_agents.definitions import Definition, Item
from clarc_agents.sentence import Sentence

ASK = "Which option fits you best? Say it, or touch it on the screen."
AGAIN = "Let me say the options again."
ASK_AGAIN = "Let me ask again."
CLARIFY = "Sorry, I did not understand."
# what the screen takes from the patient while an item of each kind is asked
INPUTS = {"choose": "options", "words": "", "touches": "targets", "drawing": "drawing"}
INPUTS |= {"eyes": "", "serial": ""}


def greet(definition: Definition, patient: str) -> Sentence:
    return Sentence(definition.sentence("greet", patient=patient))


def explain(definition: Definition) -> Sentence:
    return Sentence(definition.sentence("explain"))


def introduce(definition: Definition, key: str) -> Sentence:
    item = definition.item(key)
    position = definition.order.index(key) + 1
    return Sentence(
        f"Question {position} of {len(definition.items)}, {item.title}. {item.question}",
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


def _spoken_options(item: Item) -> str:
    return " ".join(f"Option {i + 1}: {o.text}." for i, o in enumerate(item.options))


def describe_options(definition: Definition, key: str) -> Sentence:
    item = definition.item(key)
    return _answering(f"The options are. {_spoken_options(item)}", item)


def ask(definition: Definition, key: str) -> Sentence:
    item = definition.item(key)
    return _answering(ASK if item.kind == "choose" else item.ask, item)


def options_again(definition: Definition, key: str) -> Sentence:
    """No answer in time: the options again by voice, all of them on the screen (or, for an
    item without options, the question and the request again)."""
    item = definition.item(key)
    if item.kind != "choose":
        return _answering(f"{ASK_AGAIN} {item.question} {item.ask}", item)
    return _answering(
        f"{AGAIN} {_spoken_options(item)} You can also touch one on the screen.", item
    )


def clarify(definition: Definition, key: str) -> Sentence:
    """Not understood: repeat, offer the touch screen (if the item has options), offer to
    skip."""
    item = definition.item(key)
    if item.kind != "choose":
        return _answering(f"{CLARIFY} {item.ask} Or say skip to go to the next question.", item)
    return _answering(
        f"{CLARIFY} {item.question} You can touch your answer "
        "on the screen, or say skip to go to the next question.",
        item,
    )


def sit_down() -> Sentence:
    return Sentence("Please, sit down in front of me.", needs_person=False)


def call_clinician() -> Sentence:
    return Sentence("I will ask the doctor to come and help us. We can go on meanwhile.")


def goodbye(definition: Definition, patient: str) -> Sentence:
    return Sentence(definition.sentence("goodbye", patient=patient), needs_person=False)
