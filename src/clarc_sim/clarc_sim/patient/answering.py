"""How the simulated patient answers an item so as to earn exactly the points its scenario says
(pure): the option worth them, the words with that many parts right, the shapes touched with
that many in their place, a drawing, or the eyes closed or not.

The item is from the definition filled for today and here (orientation's right answers), as the
patient, who knows the date and where they are, would answer."""

from __future__ import annotations

import math

from clarc_agents.definitions import Item

# what the patient says for what it does not know, in the item's language
DONT_KNOW = {"en": "I don't know", "es": "No lo sé"}
REST = {"en": "I don't remember the rest", "es": "No me acuerdo del resto"}


def words_for(item: Item, points: int) -> str:
    """What to say to a ``words`` item: the first ``points`` parts right, the rest not known."""
    right = [part.keywords[0] for part in item.parts[:points]]
    if not right:
        return DONT_KNOW.get(item.language, DONT_KNOW["en"])
    rest = [REST.get(item.language, REST["en"])] if points < len(item.parts) else []
    return ", ".join(right + rest)


def touches_for(item: Item, points: int) -> list[str]:
    """The shapes to touch on a ``touches`` item: the first ``points`` in their place, then a
    wrong shape for each part left."""
    touched = []
    for k, part in enumerate(item.parts):
        target = part.keywords[0]
        wrong = next(s.lower() for s in item.shows if s.lower() != target)
        touched.append(target if k < points else wrong)
    return touched


def drawing_for(item: Item, points: int) -> str:
    """SVG path data of what the patient draws: when they can (``points`` above 0), a line of
    handwriting or the two overlapping pentagons the screen shows; otherwise a scribble."""
    if points == 0:
        return "M 40 80 L 55 60 L 62 95 L 80 70"
    if "pentagons" in (s.lower() for s in item.shows):
        return " ".join(_pentagon(cx, 100) for cx in (100, 160))
    # a sentence's worth of joined-up letters along a line
    strokes = []
    for word in range(4):
        x0 = 20 + word * 70
        points_ = [(x0 + 6 * k, 100 - 18 * ((k % 3) == 1)) for k in range(9)]
        strokes.append(_path(points_))
    return " ".join(strokes)


def _pentagon(cx: float, cy: float, r: float = 45.0) -> str:
    corners = [
        (cx + r * math.sin(2 * math.pi * k / 5), cy - r * math.cos(2 * math.pi * k / 5))
        for k in range(6)
    ]
    return _path(corners)


def _path(points: list[tuple[float, float]]) -> str:
    head, *rest = points
    return f"M {head[0]:.0f} {head[1]:.0f} " + " ".join(f"L {x:.0f} {y:.0f}" for x, y in rest)
