"""What CLARC says and shows at each step of the Barthel test (pure). Each sentence says whether
it needs the patient in front of the robot (speech stops and the screen clears if they leave) and
which options, if any, the touch screen shows with it."""

from __future__ import annotations

from dataclasses import dataclass, field

from clarc_agents.barthel.items import BY_KEY, DEFINITION, ORDER


@dataclass(frozen=True)
class Sentence:
    text: str
    needs_person: bool = True
    item: str = ""
    options: list[str] = field(default_factory=list)  # shown as buttons
    option_points: list[float] = field(default_factory=list)


def greet(patient: str) -> Sentence:
    return Sentence(DEFINITION.sentence("greet", patient=patient))


def explain() -> Sentence:
    return Sentence(DEFINITION.sentence("explain"))


def introduce(item: str) -> Sentence:
    position = ORDER.index(item) + 1
    return Sentence(
        f"Question {position} of {len(ORDER)}, {BY_KEY[item].title}. {BY_KEY[item].question}",
        item=item,
    )


def _with_options(text: str, item: str) -> Sentence:
    opts = BY_KEY[item].options
    return Sentence(
        text,
        item=item,
        options=[o.text for o in opts],
        option_points=[float(o.points) for o in opts],
    )


def describe_options(item: str) -> Sentence:
    opts = BY_KEY[item].options
    spoken = " ".join(f"Option {i + 1}: {o.text}." for i, o in enumerate(opts))
    return _with_options(f"The options are. {spoken}", item)


def ask(item: str) -> Sentence:
    return _with_options("Which option fits you best? Say it, or touch it on the screen.", item)


def options_again(item: str) -> Sentence:
    """No answer in time: the options again by voice, all of them on the screen."""
    opts = BY_KEY[item].options
    spoken = " ".join(f"Option {i + 1}: {o.text}." for i, o in enumerate(opts))
    return _with_options(
        f"Let me say the options again. {spoken} You can also touch one on the screen.", item
    )


def clarify(item: str) -> Sentence:
    """Not understood: repeat, offer the touch screen, offer to skip."""
    return _with_options(
        f"Sorry, I did not understand. {BY_KEY[item].question} You can touch your answer "
        "on the screen, or say skip to go to the next question.",
        item,
    )


def sit_down() -> Sentence:
    return Sentence("Please, sit down in front of me.", needs_person=False)


def call_clinician() -> Sentence:
    return Sentence("I will ask the doctor to come and help us. We can go on meanwhile.")


def goodbye(patient: str) -> Sentence:
    return Sentence(DEFINITION.sentence("goodbye", patient=patient), needs_person=False)
