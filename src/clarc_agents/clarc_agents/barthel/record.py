"""The record of a Barthel test as it runs, item by item, and the result it gives (pure)."""

from __future__ import annotations

from dataclasses import dataclass, field

from clarc_agents.barthel.items import BY_KEY, ORDER, band

# how an answer window ended; "interrupted": cut by a restart, so the item is asked again
WINDOW_OUTCOMES = ("answered", "no_answer", "not_understood", "skip", "interrupted")


@dataclass
class ItemResult:
    item: str
    points: int | None = None  # None: unanswered
    via: str | None = None  # "voice" | "touch" | None
    attempts: int = 0  # answer windows opened for this item
    closed: bool = False  # answered, or given up on
    outcomes: list[str] = field(default_factory=list)  # how each window ended (WINDOW_OUTCOMES)
    heard: str = ""  # the last words heard that were not an answer

    @property
    def status(self) -> str:
        """As the item's node says it: answered, unanswered (closed without one) or asking."""
        if self.points is not None:
            return "answered"
        return "unanswered" if self.closed else "asking"

    def to_json(self) -> dict:
        return {
            "item": self.item,
            "points": self.points,
            "via": self.via,
            "attempts": self.attempts,
        }


@dataclass
class BarthelRecord:
    """What a Barthel test produced, item by item, as it runs."""

    patient: str
    started: str
    items: dict[str, ItemResult] = field(default_factory=lambda: {k: ItemResult(k) for k in ORDER})
    finished: str | None = None
    clinician_called: bool = False
    person_lost_count: int = 0

    def answer(self, item: str, points: int, via: str) -> None:
        if BY_KEY[item].option(points) is None:
            raise ValueError(f"{points} is not an option of {item} ({BY_KEY[item].points})")
        self.items[item].points = points
        self.items[item].via = via
        self.items[item].closed = True

    def give_up(self, item: str) -> None:
        """The item is closed without an answer."""
        self.items[item].closed = True

    @property
    def total(self) -> int:
        return sum(r.points for r in self.items.values() if r.points is not None)

    @property
    def unanswered(self) -> list[str]:
        """Items closed without an answer so far (an item still being asked is not one)."""
        return [k for k in ORDER if self.items[k].closed and self.items[k].points is None]

    def to_json(self) -> dict:
        return {
            "patient": self.patient,
            "started": self.started,
            "finished": self.finished,
            "total": self.total,
            "band": band(self.total),
            "items": [self.items[k].to_json() for k in ORDER],
            "unanswered": [k for k in ORDER if self.items[k].points is None],
            "clinician_called": self.clinician_called,
            "person_lost": self.person_lost_count > 0,
            "person_lost_count": self.person_lost_count,
        }
