"""A language the robot asks and understands questionnaires in (pure): the words the
understanding rules read and the robot's own sentences around the items, as a data file,
``clarc_agents/languages/<code>.yaml`` (format ``clarc-language``, docs/FORMAT.md "Languages"),
read strictly, so the rules of ``questionnaire/answers.py`` hold in every language and a
language is added as data. A mistake is a ``DefinitionError`` naming the file and the line.

    spanish = languages.get("es")
    spanish.weekdays, spanish.words("negators"), spanish.say("heard")
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cache
from importlib import resources
from pathlib import Path
from typing import Any

from clarc_agents.exceptions import DefinitionError
from clarc_agents.yaml_lines import compose, err, fields, scalar

DEFAULT = "en"
DE = DefinitionError  # every mistake in a language file
WORD_LISTS = (
    "skip",
    "hesitations",
    "unknowing",
    "position_words",
    "ordinal_followers",
    "last",
    "definite_articles",
    "articles",
    "negators",
    "negating_endings",
    "clause_ends",
    "hedges",
    "operators",
    "corrections",
    "weekdays",
    "months",
    "yes_words",
    "no_words",
    "option_numbers",
    "no_option",
)
# what the robot says around a questionnaire's items (questionnaire/sentences.py, confirmation.py)
SENTENCES = (
    "introduce",
    "options_are",
    "option",
    "ask",
    "again",
    "touch_too",
    "ask_again",
    "clarify",
    "clarify_choose",
    "clarify_words",
    "sit_down",
    "call_clinician",
    "heard",
    "is_it_right",
    "confirm",
    "points",
    "yes",
    "no",
)
KEYS = ("format", "version", "language", "name", *WORD_LISTS, "seasons", "sentences")


@dataclass(frozen=True)
class Language:
    code: str  # ISO 639-1, as Whisper and espeak-ng name it
    name: str
    lists: dict[str, tuple[str, ...]]  # WORD_LISTS: each a tuple of words or phrases
    seasons: tuple[tuple[str, ...], ...]  # winter, spring, summer, autumn: the ways of each
    sentences: dict[str, str]  # SENTENCES

    def say(self, name: str, **values: object) -> str:
        """The robot's sentence ``name`` with its ``{...}`` filled in."""
        return self.sentences[name].format(**values)

    def __getattr__(self, name: str) -> tuple[str, ...]:
        lists = self.__dict__.get("lists", {})
        if name in lists:
            return lists[name]
        raise AttributeError(name)

    def words(self, name: str) -> frozenset[str]:
        """A list of single words, as a set (``negators``, ``clause_ends``, ...)."""
        return frozenset(self.lists[name])

    def season(self, month: int) -> tuple[str, ...]:
        """The ways of saying the season of ``month`` (meteorological, northern hemisphere)."""
        return self.seasons[month % 12 // 3]


@cache
def codes() -> tuple[str, ...]:
    """The languages shipped with the package."""
    folder = resources.files("clarc_agents").joinpath("languages")
    return tuple(sorted(p.name[:-5] for p in folder.iterdir() if p.name.endswith(".yaml")))


def path_of(code: str) -> Path:
    return Path(str(resources.files("clarc_agents").joinpath(f"languages/{code}.yaml")))


@cache
def get(code: str = DEFAULT) -> Language:
    """The language ``code`` shipped with the package (read once)."""
    if code not in codes():
        raise DefinitionError(f"no language {code!r} (there are: {', '.join(codes())})")
    path = path_of(code)
    language = parse(path.read_text(encoding="utf-8"), str(path))
    if language.code != code:
        raise DefinitionError(f"{path}: says language {language.code!r}, its name says {code!r}")
    return language


def parse(text: str, source: str = "language") -> Language:
    root = compose(text, source, DefinitionError)
    top = fields(source, root, KEYS, "", (), DefinitionError)
    if scalar(top["format"][1]) != "clarc-language" or scalar(top["version"][1]) != 1:
        raise err(source, top["format"][1], "this reads format clarc-language, version 1", DE)
    code, name = _text(source, top, "language"), _text(source, top, "name")
    lists = {key: _list(source, top[key][1], key) for key in WORD_LISTS}
    for key, count in (("weekdays", 7), ("months", 12)):
        if len(lists[key]) != count:
            raise err(source, top[key][1], f"{key} lists {count}, got {len(lists[key])}", DE)
    seasons_node = top["seasons"][1]
    seasons = tuple(_list(source, n, "a season") for n in getattr(seasons_node, "value", []))
    if len(seasons) != 4 or not all(seasons):
        raise err(source, seasons_node, "seasons lists winter, spring, summer, autumn", DE)
    sentences_node = top["sentences"][1]
    said = fields(source, sentences_node, SENTENCES, "sentences: ", (), DE)
    sentences = {key: _text(source, said, key) for key in SENTENCES}
    return Language(code, name, lists, seasons, sentences)


def _text(source: str, top: dict[str, tuple[Any, Any]], key: str) -> str:
    value = scalar(top[key][1])
    if not isinstance(value, str) or not value.strip():
        raise err(source, top[key][1], f"{key} must be a text", DE)
    return value.strip()


def _list(source: str, node: Any, what: str) -> tuple[str, ...]:
    """A list of texts (numbers are written as texts: "1")."""
    values = getattr(node, "value", None)
    if not isinstance(values, list):
        raise err(source, node, f"{what} is a list", DE)
    out = []
    for item in values:
        value = scalar(item) if not isinstance(getattr(item, "value", None), list) else None
        if not isinstance(value, str) or not value.strip():
            raise err(source, item, f"{what}: each is a text", DE)
        out.append(value.strip())
    return tuple(out)
