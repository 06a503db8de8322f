"""The Barthel index (Mahoney & Barthel, 1965): its ten items, their options and points, and the
dependency bands of a total, as its test definition says (definitions/barthel.yaml). Pure.

Each option has the text the robot reads out and shows, the phrase a patient typically says for
it (the simulated patient uses it), and keywords the Speech agent recognises it by.
"""

from __future__ import annotations

from clarc_agents.definitions import Item, Option, load

DEFINITION = load("barthel")  # definitions/barthel.yaml: the one copy of the table
ITEMS: tuple[Item, ...] = DEFINITION.items
__all__ = ["BANDS", "BY_KEY", "DEFINITION", "ITEMS", "MAX_TOTAL", "ORDER", "Item", "Option", "band"]

BY_KEY: dict[str, Item] = {item.key: item for item in ITEMS}
ORDER: tuple[str, ...] = tuple(item.key for item in ITEMS)
MAX_TOTAL = DEFINITION.max_total
assert MAX_TOTAL == 100

BANDS = DEFINITION.bands


def band(total: int) -> str:
    """Dependency band of a Barthel total: total (0-20), severe (21-60), moderate (61-90),
    slight (91-99), independent (100)."""
    return DEFINITION.band(total)
