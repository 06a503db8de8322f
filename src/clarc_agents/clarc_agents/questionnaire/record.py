"""The record of a questionnaire test as it runs, item by item, and the result it gives (pure).
Which items, their maxima and the bands come from the test's definition."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

from clarc_agents.definitions import Definition, Item

# how an answer window ended; "interrupted": cut by a restart, so the item is asked again;
# "unsure": an option heard, not for sure, confirmed with the patient
WINDOW_OUTCOMES = ("answered", "no_answer", "not_understood", "unsure", "skip", "interrupted")


@dataclass
class ItemResult:
    item: str
    points: int | None = None  # None: unanswered, or waiting for the clinician to score it
    via: str | None = None  # "voice" | "touch" | "camera" | None
    attempts: int = 0  # answer windows opened for this item, but those nobody could be heard in
    closed: bool = False  # answered, or given up on
    outcomes: list[str] = field(default_factory=list)  # how each window ended (WINDOW_OUTCOMES)
    heard: str = ""  # the last words heard (or targets touched) for it
    drawing: str = ""  # what the patient drew (SVG path data), for the clinician to score
    answered: bool = False  # an answer came (for a drawing: before the clinician scored it)
    audio: list[str] = field(default_factory=list)  # the clips of what was said to it
    # what was heard in its windows that ended not understood, and how sure: a words or serial
    # answer heard the same again is taken (questionnaire/agreement.py)
    hearings: list[tuple[str, float]] = field(default_factory=list)

    @property
    def doubtful(self) -> bool:
        """Closed without an answer after words the robot did not understand: the clinician
        scores it from what was heard and its clips, never 0 by default (a skip asked for by
        the patient is no doubt)."""
        return (
            self.closed
            and not self.answered
            and self.points is None
            and "not_understood" in self.outcomes
            and "skip" not in self.outcomes
        )

    @property
    def status(self) -> str:
        """As the item's node says it: answered, unanswered (closed without one) or asking."""
        if self.answered or self.points is not None:
            return "answered"
        return "unanswered" if self.closed else "asking"

    def to_json(self, item: Item) -> dict[str, Any]:
        result: dict[str, Any] = {
            "item": self.item,
            "points": self.points,
            "via": self.via,
            "attempts": self.attempts,
            "max": item.max,
            "needs_clinician": item.needs_clinician or self.doubtful,
        }
        answer = answer_text(item, self)
        if answer:
            result["answer"] = answer
        if self.drawing:
            result["drawing"] = self.drawing
        if self.doubtful and self.heard:
            result["heard"] = self.heard
        if self.audio:
            result["audio"] = list(self.audio)
        return result


def answer_text(item: Item, result: ItemResult) -> str:
    """The answer in words, as a clinician reads it: the option chosen, the words heard, the
    targets touched, whether the eyes closed."""
    if not result.answered and result.points is None:
        return ""
    if item.kind == "choose" and result.points is not None:
        option = item.option(result.points)
        return option.text if option is not None else ""
    if item.kind == "eyes":
        return "closed the eyes" if result.points else "did not close the eyes"
    if item.kind == "drawing":
        return "drew on the screen" if result.drawing else ""
    return result.heard


@dataclass
class QuestionnaireRecord:
    """What a questionnaire test produced, item by item, as it runs."""

    definition: Definition
    patient: str
    started: str
    items: dict[str, ItemResult] = field(default_factory=dict)
    finished: str | None = None
    clinician_called: bool = False
    person_lost_count: int = 0
    patient_id: int | None = None  # the patient's record in CGAmed, if Start named it

    def __post_init__(self) -> None:
        for key in self.definition.order:
            self.items.setdefault(key, ItemResult(key))

    def answer(self, item: str, points: int | None, via: str, heard: str = "", drawing: str = ""):
        """An answer came: its points (None for a drawing the clinician scores)."""
        spec = self.definition.item(item)
        if points is None and not spec.needs_clinician:
            raise ValueError(f"{item} is scored when answered: its points are needed")
        if points is not None and points not in spec.points:
            raise ValueError(f"{points} is not a score of {item} ({list(spec.points)})")
        result = self.items[item]
        result.points, result.via, result.closed, result.answered = points, via, True, True
        if heard and spec.kind != "choose":  # what was said or touched is the answer's content
            result.heard = heard
        result.drawing = drawing

    def give_up(self, item: str) -> None:
        """The item is closed without an answer."""
        self.items[item].closed = True

    @property
    def total(self) -> int:
        """The points scored so far."""
        return sum(r.points for r in self.items.values() if r.points is not None)

    @property
    def unanswered(self) -> list[str]:
        """Items closed without an answer so far (an item still being asked is not one)."""
        return [
            k for k in self.definition.order if self.items[k].closed and not self.items[k].answered
        ]

    @property
    def complete(self) -> bool:
        """No item waits for the clinician's score."""
        return (
            all(
                self.items[i.key].points is not None
                for i in self.definition.items
                if i.needs_clinician
            )
            and not self.doubtful
        )

    @property
    def doubtful(self) -> list[str]:
        """Items the robot could not understand, which the clinician scores."""
        return [k for k in self.definition.order if self.items[k].doubtful]

    @property
    def total_range(self) -> list[int]:
        """The least and the most the total can be once the doubtful items are scored."""
        most = sum(self.definition.item(k).max for k in self.doubtful)
        return [self.total, self.total + most]

    def to_json(self) -> dict[str, Any]:
        order = self.definition.order
        patient_id = {} if self.patient_id is None else {"patient_id": self.patient_id}
        return {
            **patient_id,
            "test": self.definition.test,
            "patient": self.patient,
            "started": self.started,
            "finished": self.finished,
            "total": self.total,
            "max_total": self.definition.max_total,
            # a result with items the robot could not understand has no band until the
            # clinician scores them: only the range the total lies in
            "band": None if self.doubtful else self.definition.band(self.total),
            "provisional": bool(self.doubtful),
            "total_range": self.total_range,
            "complete": self.complete,
            "items": [self.items[i.key].to_json(i) for i in self.definition.items],
            "unanswered": [k for k in order if not self.items[k].answered],
            "clinician_called": self.clinician_called,
            "person_lost": self.person_lost_count > 0,
            "person_lost_count": self.person_lost_count,
        }
