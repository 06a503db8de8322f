"""The Barthel index's table as the tests name it (its items, order, total and bands), read from
its test definition (definitions/barthel.yaml): the robot itself reads it only as data."""

from clarc_agents.definitions import load

DEFINITION = load("barthel")
ITEMS = DEFINITION.items
BY_KEY = {item.key: item for item in ITEMS}
ORDER = tuple(item.key for item in ITEMS)
MAX_TOTAL = DEFINITION.max_total


def band(total: int) -> str:
    """Dependency band of a Barthel total: total (0-20), severe (21-60), moderate (61-90),
    slight (91-99), independent (100)."""
    return DEFINITION.band(total)
