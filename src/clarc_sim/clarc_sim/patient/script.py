"""What the simulated patient does when it hears CLARC (pure; the node runs the actions).

The patient reacts to sentences, as a person would: it recognises the question of an item, the
request to answer, the options said again, and the "did not understand" repetition, and answers
according to its scenario. ``heard(text, event)`` returns the actions to take, each after a delay
in seconds of a real session (the node scales them).
"""

from __future__ import annotations

from dataclasses import dataclass

from clarc_agents.barthel.items import BY_KEY, ITEMS
from clarc_sim.patient.scenario import Scenario

GARBLED = "mmh... the, eh... brr"
ASK = "Which option fits you best?"
AGAIN = "Let me say the options again."
CLARIFY = "Sorry, I did not understand."


@dataclass(frozen=True)
class Action:
    kind: str  # "say" (text), "tap" (points), "leave" (seconds away)
    delay: float
    text: str = ""
    points: int | None = None
    seconds: float = 0.0


class PatientScript:
    def __init__(self, scenario: Scenario, reaction: float = 1.0):
        self.scenario = scenario
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
            (i.key for i in ITEMS if i.question in text and text.startswith("Question")), None
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
        if text.startswith(ASK):
            if self.item not in self._first_done:
                self._first_done.add(self.item)
                first = self.scenario.plan(self.item).first
                if first == "silence":
                    return []
                if first == "garbled":
                    return [Action("say", self.reaction, text=GARBLED)]
            return self._answer()
        if text.startswith(AGAIN) or text.startswith(CLARIFY):
            return self._answer()
        return []

    def _answer(self) -> list[Action]:
        plan = self.scenario.plan(self.item)
        if plan.via == "silence":
            return []
        if plan.via == "touch":
            return [Action("tap", self.reaction, points=plan.answer)]
        return [Action("say", self.reaction, text=BY_KEY[self.item].option(plan.answer).says)]
