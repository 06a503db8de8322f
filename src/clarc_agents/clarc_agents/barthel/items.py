"""The Barthel index (Mahoney & Barthel, 1965): its ten items, their options and points, and the
dependency bands of a total. Pure data; no ROS.

Each option has the text the robot reads out and shows, the phrase a patient typically says for
it (the simulated patient uses it), and keywords the Speech agent recognises it by.
"""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class Option:
    points: int
    text: str  # read out and shown on the touch screen
    says: str  # what a patient says to choose it
    keywords: tuple[str, ...]  # what recognises it in an utterance (lower case)


@dataclass(frozen=True)
class Item:
    key: str
    title: str
    question: str
    options: tuple[Option, ...]

    @property
    def points(self) -> tuple[int, ...]:
        return tuple(o.points for o in self.options)

    def option(self, points: int) -> Option | None:
        return next((o for o in self.options if o.points == points), None)


def _item(key, title, question, *options) -> Item:
    return Item(key, title, question, tuple(Option(*o) for o in options))


ITEMS: tuple[Item, ...] = (
    _item(
        "feeding",
        "Feeding",
        "Can you eat by yourself?",
        (
            0,
            "I cannot eat without help",
            "I cannot eat without help",
            ("cannot eat", "can't eat", "unable to eat"),
        ),
        (
            5,
            "I need help cutting or spreading",
            "I need some help cutting the food",
            ("cutting", "spreading", "some help"),
        ),
        (10, "I eat by myself", "I eat on my own", ("by myself", "on my own", "independent")),
    ),
    _item(
        "bathing",
        "Bathing",
        "Can you bathe or shower by yourself?",
        (0, "I need help to bathe", "I need help to bathe", ("need help", "cannot", "can't")),
        (5, "I bathe by myself", "I bathe on my own", ("by myself", "on my own", "independent")),
    ),
    _item(
        "grooming",
        "Grooming",
        "Can you wash your face, comb your hair and brush your teeth by yourself?",
        (
            0,
            "I need help with personal care",
            "I need help with that",
            ("need help", "cannot", "can't"),
        ),
        (5, "I do it by myself", "I do it on my own", ("by myself", "on my own", "independent")),
    ),
    _item(
        "dressing",
        "Dressing",
        "Can you get dressed by yourself, with buttons and zips?",
        (
            0,
            "I cannot dress without help",
            "I cannot dress without help",
            ("cannot dress", "can't dress", "unable"),
        ),
        (
            5,
            "I need help, but do about half",
            "I need some help, I do about half",
            ("half", "some help"),
        ),
        (10, "I dress by myself", "I dress on my own", ("by myself", "on my own", "independent")),
    ),
    _item(
        "bowels",
        "Bowels",
        "Do you control your bowels?",
        (
            0,
            "I do not control them",
            "No, I do not control them",
            ("do not control", "don't control", "no"),
        ),
        (
            5,
            "I have an occasional accident",
            "I have an accident sometimes",
            ("occasional", "accident", "sometimes"),
        ),
        (10, "I control them", "Yes, I control them", ("yes", "always", "i control")),
    ),
    _item(
        "bladder",
        "Bladder",
        "Do you control your bladder?",
        (
            0,
            "I do not control it",
            "No, I do not control it",
            ("do not control", "don't control", "no"),
        ),
        (
            5,
            "I have an occasional accident",
            "I have an accident sometimes",
            ("occasional", "accident", "sometimes"),
        ),
        (10, "I control it", "Yes, I control it", ("yes", "always", "i control")),
    ),
    _item(
        "toilet_use",
        "Toilet use",
        "Can you use the toilet by yourself?",
        (0, "I depend on others", "I depend on others for that", ("depend", "dependent")),
        (5, "I need some help", "I need some help", ("some help", "a bit of help")),
        (10, "I use it by myself", "I use it on my own", ("by myself", "on my own", "independent")),
    ),
    _item(
        "transfers",
        "Transfers",
        "Can you move from your bed to a chair and back?",
        (
            0,
            "I cannot, I have no balance",
            "I cannot do it at all",
            ("cannot", "can't", "no balance"),
        ),
        (
            5,
            "I need major help, one or two people",
            "I need two people to help me",
            ("major help", "two people"),
        ),
        (10, "I need a little help", "I need a little help", ("a little help", "minor help")),
        (15, "I do it by myself", "I do it on my own", ("by myself", "on my own", "independent")),
    ),
    _item(
        "mobility",
        "Mobility",
        "Can you walk on a level surface?",
        (0, "I cannot walk", "I cannot walk", ("cannot walk", "can't walk", "immobile")),
        (5, "I use a wheelchair by myself", "I get around in my wheelchair", ("wheelchair",)),
        (
            10,
            "I walk with the help of one person",
            "I walk if someone helps me",
            ("someone helps", "one person"),
        ),
        (
            15,
            "I walk by myself",
            "I walk on my own",
            ("walk by myself", "walk on my own", "independent"),
        ),
    ),
    _item(
        "stairs",
        "Stairs",
        "Can you go up and down stairs?",
        (0, "I cannot use stairs", "I cannot use the stairs", ("cannot", "can't", "unable")),
        (5, "I need help on stairs", "I need help on the stairs", ("need help",)),
        (
            10,
            "I use stairs by myself",
            "I use them on my own",
            ("by myself", "on my own", "independent"),
        ),
    ),
)

BY_KEY: dict[str, Item] = {item.key: item for item in ITEMS}
ORDER: tuple[str, ...] = tuple(item.key for item in ITEMS)
MAX_TOTAL = sum(max(i.points) for i in ITEMS)
assert MAX_TOTAL == 100

BANDS = (
    (0, 20, "total"),
    (21, 60, "severe"),
    (61, 90, "moderate"),
    (91, 99, "slight"),
    (100, 100, "independent"),
)


def band(total: int) -> str:
    """Dependency band of a Barthel total: total (0-20), severe (21-60), moderate (61-90),
    slight (91-99), independent (100)."""
    for low, high, name in BANDS:
        if low <= total <= high:
            return name
    raise ValueError(f"a Barthel total is between 0 and 100, got {total}")
