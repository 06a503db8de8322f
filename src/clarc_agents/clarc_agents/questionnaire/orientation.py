"""What orientation is scored against (pure): the real date and the configured place, as the
values of a definition's placeholders ({year}, {season}, {date}, {weekday}, {month};
{country}, {province}, {city}, {building}, {floor}). Each value is every way of saying it that
counts as right."""

from __future__ import annotations

from datetime import date

from clarc_agents import languages
from clarc_agents.exceptions import DefinitionError
from clarc_agents.questionnaire.spoken import ORDINAL_DIGITS, suffixed, words

PLACE_PARTS = ("country", "province", "city", "building", "floor")
# Where CLARC runs the tests (the paper's hospital); "|" between the ways of saying one part.
DEFAULT_PLACE = (
    "Spain",
    "Andalusia|Seville province",
    "Seville",
    "Hospital Universitario Virgen del Rocio|Virgen del Rocio",
    "first floor",
)
# The default place as a test in another language says it: its names in that language first
# (the simulated patient says a part's first way), the English ones still right. A configured
# place is used as it is in every language: a site lists every way it accepts.
DEFAULT_PLACE_IN = {
    "es": (
        "España|Spain",
        "Andalucía|provincia de Sevilla|Andalusia|Seville province",
        "Sevilla|Seville",
        "Hospital Universitario Virgen del Rocío|Virgen del Rocío|Virgen del Rocio",
        "primera planta|planta primera|primer piso|la primera|first floor",
    ),
}
# The names of the days, months and seasons are the test's language's (clarc_agents/languages/),
# whatever the machine's locale; the seasons are the meteorological ones of the northern
# hemisphere (where the place is). English's, for the recogniser's vocabularies:
_ENGLISH = languages.get("en")
SEASONS = {m: _ENGLISH.season(m)[0] for m in range(1, 13)}
SEASON_WORDS = {ways[0]: ways for ways in _ENGLISH.seasons if len(ways) > 1}
WEEKDAYS = _ENGLISH.weekdays
MONTHS = _ENGLISH.months


def place_values(place: tuple[str, ...] | list[str]) -> dict[str, tuple[str, ...]]:
    """The five parts of the place (country, province, city, building, floor)."""
    if len(place) != len(PLACE_PARTS):
        raise DefinitionError(
            f"the place has {len(PLACE_PARTS)} parts ({', '.join(PLACE_PARTS)}), got {list(place)}"
        )
    values = {}
    for name, text in zip(PLACE_PARTS, place, strict=True):
        ways = tuple(w.strip() for w in str(text).split("|") if w.strip())
        if not ways:
            raise DefinitionError(f"the place's {name} is empty")
        values[name] = ways + (_floor_variants(ways) if name == "floor" else ())
    return values


def _floor_variants(ways: tuple[str, ...]) -> tuple[str, ...]:
    """A floor said as an ordinal ("first floor") is right said as "floor one" or, in answer to
    "which floor", as the ordinal alone ("the first")."""
    variants = []
    for way in ways:
        said = words(way)
        if len(said) == 2 and said[1] == "floor" and (n := ORDINAL_DIGITS.match(said[0])):
            variants += [f"floor {n[1]}", said[0]]
    return tuple(v for v in dict.fromkeys(variants) if v not in ways)


def date_values(today: date, code: str = languages.DEFAULT) -> dict[str, tuple[str, ...]]:
    said_in = languages.get(code)
    return {
        "year": (str(today.year),),
        "season": said_in.season(today.month),
        "date": (str(today.day), suffixed(today.day)),
        "weekday": (said_in.weekdays[today.weekday()],),
        "month": (said_in.months[today.month - 1],),
    }


def values(
    today: date,
    place: tuple[str, ...] | list[str] = DEFAULT_PLACE,
    code: str = languages.DEFAULT,
):
    """Every placeholder's values on ``today`` at ``place``, the date's said in ``code`` (and
    the default place's, ``DEFAULT_PLACE_IN``)."""
    if tuple(place) == DEFAULT_PLACE:
        place = DEFAULT_PLACE_IN.get(code, DEFAULT_PLACE)
    return date_values(today, code) | place_values(place)
