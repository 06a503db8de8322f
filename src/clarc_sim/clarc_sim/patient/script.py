"""What the simulated patient does when it hears CLARC (pure; the node runs the actions).

The patient reacts to sentences, as a person would: it recognises the question of an item, the
request to answer, the options said again, the question asked again, the "did not
understand" repetition and "I heard: ... Is that right?" (yes when it is the option meant), in
the test's language (the robot's sentences of clarc_agents/languages/<code>.yaml), and answers
according to its scenario, the way the item is answered (``answering.py``). ``heard(text,
event)`` returns the actions to take, each after a delay in seconds of a real session (the node
scales them).
"""

from __future__ import annotations

from dataclasses import dataclass

from clarc_agents import languages
from clarc_agents.definitions import Definition
from clarc_sim.patient.answering import drawing_for, touches_for, words_for
from clarc_sim.patient.scenario import Scenario

# what the patient says of its own, in each language: a mumble no recogniser makes an answer
# of, and its yes and no to a read-back answer
GARBLED = {"en": "mmh... the, eh... brr", "es": "mmm... el, eh... brr"}
CONFIRMS = {"en": ("Yes, that's right.", "No."), "es": ("Sí, eso es.", "No.")}
EYES_CLOSED = 3.0  # seconds the patient keeps the eyes closed when asked to
TOUCH_GAP = 0.8  # seconds between the shapes touched one after the other


@dataclass(frozen=True)
class Action:
    kind: str  # "say" (text), "tap" (points), "touch" (target), "draw" (drawing), "leave"
    # (seconds away), "close_eyes" (seconds closed)
    delay: float
    text: str = ""
    points: int | None = None
    seconds: float = 0.0


class PatientScript:
    def __init__(self, scenario: Scenario, definition: Definition, reaction: float = 1.0):
        """``definition``: the scenario's test, filled for today and here (what the patient
        knows of the date and the place)."""
        self.scenario = scenario
        self.definition = definition
        self.said_in = said_in = languages.get(definition.language)
        self.asked = said_in.sentences["introduce"].split("{")[0]  # "Question "
        self.ask = said_in.say("ask")
        self.again = tuple(said_in.say(k) for k in ("again", "clarify", "ask_again"))
        self.heard_prefix = said_in.say("heard")  # "I heard:"
        self.reaction = reaction
        self.item: str | None = None  # the item being asked, from the last question heard
        self._left: set[str] = set()
        self._first_done: set[str] = set()
        self.present = True

    def heard(self, text: str, event: str) -> list[Action]:
        """A sentence started ("start") or ended ("end") on the speaker."""
        if not self.present:
            return []
        item = next(
            (
                i.key
                for i in self.definition.items
                if i.question in text and text.startswith(self.asked)
            ),
            None,
        )
        if item is not None and event == "start":
            self.item = item
            plan = self.scenario.plan(item)
            if plan.leave is not None and item not in self._left:
                self._left.add(item)  # walks away while being asked, once
                return [Action("leave", 0.0, seconds=plan.leave)]
            return []
        if event != "end" or self.item is None:
            return []
        spec = self.definition.item(self.item)
        if text.startswith(self.heard_prefix):  # "I heard: ... Is that right?"
            return self._confirm(spec, text)
        if text.startswith(self.ask) or (spec.kind != "choose" and text == spec.ask):
            if self.item not in self._first_done:
                self._first_done.add(self.item)
                first = self.scenario.plan(self.item).first
                if first == "silence":
                    return []
                if first == "garbled":
                    mumble = GARBLED.get(self.said_in.code, GARBLED["en"])
                    return [Action("say", self.reaction, text=mumble)]
            return self._answer()
        if text.startswith(self.again):
            return self._answer()
        return []

    def _confirm(self, spec, text: str) -> list[Action]:
        """Yes if the robot heard the option the patient meant, else no."""
        plan = self.scenario.plan(self.item)
        meant = spec.option(plan.answer) if spec.kind == "choose" else None
        right = meant is not None and text.startswith(f"{self.heard_prefix} {meant.text}.")
        yes, no = CONFIRMS.get(self.said_in.code, CONFIRMS["en"])
        return [Action("say", self.reaction, text=yes if right else no)]

    def _answer(self) -> list[Action]:
        plan = self.scenario.plan(self.item)
        spec = self.definition.item(self.item)
        if plan.via == "silence":
            return []
        if spec.kind in ("words", "serial"):
            return [Action("say", self.reaction, text=words_for(spec, plan.answer))]
        if spec.kind == "touches":
            targets = touches_for(spec, plan.answer)
            return [
                Action("touch", self.reaction + k * TOUCH_GAP, text=target)
                for k, target in enumerate(targets)
            ]
        if spec.kind == "drawing":
            return [Action("draw", self.reaction, text=drawing_for(spec, plan.answer))]
        if spec.kind == "eyes":
            return [Action("close_eyes", self.reaction, seconds=EYES_CLOSED)] if plan.answer else []
        if plan.via == "touch":
            return [Action("tap", self.reaction, points=plan.answer)]
        return [Action("say", self.reaction, text=spec.option(plan.answer).says)]
