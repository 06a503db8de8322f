"""Test definitions: a questionnaire test as a data file (``<test>.yaml`` in this package), read
strictly (pure). A mistake is a ``DefinitionError`` naming the file and the line.

    definition = load("barthel")
    definition.items[0].options[0].words, definition.band(85), definition.sentence("greet", ...)

Format (docs/FORMAT.md "Test definitions"): ``format: clarc-test``, ``version: 1``, ``test``,
``title``, ``scoring: sum``, ``sentences`` (greet, explain, goodbye; ``{patient}`` is filled
in), ``bands`` (``{name, min, max}`` covering every total from 0 to the maximum once), ``items``
in order (``key``, ``title``, ``question``, and how the item is answered: its ``kind``).

Kinds of item (how the patient answers and how it is scored; ``via`` is how the answer comes):
    choose   ``options`` ({points, text, says, words}): one is chosen by voice or touch
    words    ``parts`` ({name, words}): a point per part recognised in what is said (voice)
    serial   ``parts``: the numbers of a serial subtraction in order (93, 86, ...); a point
             per number said that is the one before it (or the start) minus the step, so one
             slip costs one point, not the rest (voice)
    touches  ``parts`` and ``shows`` (targets on the screen): a point per stage touched in
             the parts' order, other touches between them ignored (touch)
    drawing  what the patient draws on the screen is recorded; ``shows`` a model to copy, if
             any; ``points`` the maximum; the clinician scores it (``needs_clinician``)
    eyes     ``shows`` a written instruction; ``points`` if the camera sees the eyes stay closed
             a second
             while the answer is awaited, 0 if asked twice without (camera)
Every kind but ``choose`` has ``ask``: the sentence asking for the answer. A part's words may
hold placeholders filled in when a test starts (``Definition.filled``): see ``PLACEHOLDERS``.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, replace
from functools import cache
from importlib import resources
from pathlib import Path
from typing import Any

import yaml

from clarc_agents import languages as lang
from clarc_agents.exceptions import DefinitionError
from clarc_agents.yaml_lines import compose, err, fields, mapping, scalar

SENTENCES = ("greet", "explain", "goodbye")
TOP = ("format", "version", "test", "title", "scoring", "sentences", "bands", "items")
COMMON_KEYS = ("key", "title", "question")
# the keys of an item of each kind, beyond key, title and question (``kind`` may be left out
# for ``choose``)
KIND_KEYS = {
    "choose": ("options",),
    "words": ("ask", "parts"),
    "serial": ("ask", "parts"),
    "touches": ("ask", "parts", "shows"),
    "drawing": ("ask", "points"),
    "eyes": ("ask", "points", "shows"),
}
OPTIONAL_KEYS = {"drawing": ("shows",), "words": ("shows",)}
KINDS = tuple(KIND_KEYS)
VIA = {"choose": ("voice", "touch"), "words": ("voice",), "serial": ("voice",)}
VIA["touches"] = ("touch",)
VIA.update(drawing=("touch",), eyes=("camera",))
OPTION_KEYS = ("points", "text", "says", "words")
PART_KEYS = ("name", "words")
# what a part's words may hold, filled in when a test starts (questionnaire/orientation.py)
PLACEHOLDERS = (
    "year",
    "season",
    "date",
    "weekday",
    "month",
    "country",
    "province",
    "city",
    "building",
    "floor",
)


@dataclass(frozen=True)
class Option:
    points: int
    text: str  # read out and shown on the touch screen
    says: str  # what a patient says to choose it (the simulated patient, the tests)
    keywords: tuple[str, ...]  # what recognises it in an utterance (lower case)


@dataclass(frozen=True)
class Part:
    name: str
    keywords: tuple[str, ...]  # what recognises it (lower case); a touch target: the first
    # the first of them as written, a name with its capitals ("Seville", "Tuesday"): a
    # recogniser's context is spelt as the recogniser writes it ("" when not known)
    spelt: str = ""


@dataclass(frozen=True)
class Item:
    key: str
    title: str
    question: str
    options: tuple[Option, ...] = ()
    kind: str = "choose"
    parts: tuple[Part, ...] = ()
    shows: tuple[str, ...] = ()  # on the screen with the request to answer
    ask: str = ""  # the request to answer (every kind but choose)
    most: int = 0  # drawing and eyes: the points they are worth
    language: str = "en"  # what it is asked and answered in (clarc_agents/languages/)

    @property
    def points(self) -> tuple[int, ...]:
        """Every score the item can have."""
        if self.kind == "choose":
            return tuple(o.points for o in self.options)
        return tuple(range(self.max + 1))

    @property
    def max(self) -> int:
        if self.kind == "choose":
            return max(o.points for o in self.options)
        return len(self.parts) if self.parts else self.most

    @property
    def needs_clinician(self) -> bool:
        """Scored by the clinician, from what was recorded."""
        return self.kind == "drawing"

    @property
    def via(self) -> tuple[str, ...]:
        """How its answer can come: voice, touch or camera."""
        return VIA[self.kind]

    def option(self, points: int) -> Option | None:
        return next((o for o in self.options if o.points == points), None)


@dataclass(frozen=True)
class Definition:
    test: str
    title: str
    items: tuple[Item, ...]
    bands: tuple[tuple[int, int, str], ...]  # (min, max, name), in order
    sentences: dict[str, str]
    source: str = ""
    language: str = "en"

    @property
    def max_total(self) -> int:
        return sum(i.max for i in self.items)

    @property
    def order(self) -> tuple[str, ...]:
        return tuple(i.key for i in self.items)

    def item(self, key: str) -> Item:
        return next(i for i in self.items if i.key == key)

    def filled(self, values: dict[str, tuple[str, ...]]) -> Definition:
        """The definition with each placeholder in a part's words replaced by its values (a
        phrase with ``{year}`` becomes one phrase per way of saying the year)."""
        items = []
        for item in self.items:
            parts = tuple(
                Part(
                    p.name,
                    tuple(w for k in p.keywords for w in _fill(k, values)),
                    _fill(p.spelt, values, lower=False)[0] if p.spelt else "",
                )
                for p in item.parts
            )
            items.append(replace(item, parts=parts))
        return replace(self, items=tuple(items))

    def band(self, total: int) -> str:
        for low, high, name in self.bands:
            if low <= total <= high:
                return name
        raise ValueError(f"a {self.title} total is between 0 and {self.max_total}, got {total}")

    def sentence(self, name: str, **values: str) -> str:
        return self.sentences[name].format(**values)


_PLACEHOLDER = re.compile(r"\{(\w+)\}")


def _fill(phrase: str, values: dict[str, tuple[str, ...]], lower: bool = True) -> tuple[str, ...]:
    found = _PLACEHOLDER.search(phrase)
    if found is None:
        return (phrase,)
    return tuple(
        filled
        for value in values[found.group(1)]
        for filled in _fill(
            phrase.replace(found.group(0), value.lower() if lower else value, 1), values, lower
        )
    )


@cache
def tests() -> tuple[str, ...]:
    """The questionnaire tests shipped with the package."""
    folder = resources.files("clarc_agents").joinpath("definitions")
    return tuple(sorted(p.name[:-5] for p in folder.iterdir() if p.name.endswith(".yaml")))


def path_of(test: str, language: str = "en") -> Path:
    """English definitions are ``definitions/<test>.yaml``, the others
    ``definitions/<language>/<test>.yaml``: the same test, item for item, in that language."""
    inside = f"{test}.yaml" if language == "en" else f"{language}/{test}.yaml"
    return Path(str(resources.files("clarc_agents").joinpath(f"definitions/{inside}")))


def languages(test: str) -> tuple[str, ...]:
    """The languages ``test`` is shipped in."""
    found = [code for code in lang.codes() if path_of(test, code).is_file()]
    return tuple(found)


@cache
def load(test: str, language: str = "en") -> Definition:
    """The definition of ``test`` in ``language`` shipped with the package (read once)."""
    lang.get(language)  # a language there is (never a path): DefinitionError naming them
    path = path_of(test, language)
    try:
        text = path.read_text(encoding="utf-8")
    except OSError as e:
        raise DefinitionError(
            f"{path}: cannot read the definition of {test!r} in {language!r} "
            f"(it is shipped in: {', '.join(languages(test)) or 'none'}): {e.strerror}"
        ) from None
    definition = parse(text, str(path))
    if definition.language != language:
        raise DefinitionError(f"{path}: says language {definition.language!r}, not {language!r}")
    return definition


def parse(text: str, source: str = "definition") -> Definition:
    root = compose(text, source, DefinitionError)
    if not isinstance(root, _Mapping):
        raise _err(source, root, "a test definition is a mapping (format: clarc-test, ...)")
    top = _fields(source, root, TOP, "", ("language",))
    if _value(top, "format") != "clarc-test" or _value(top, "version") != 1:
        raise _err(source, top["format"][1], "this reads format clarc-test, version 1")
    if _value(top, "scoring") != "sum":
        raise _err(source, top["scoring"][1], "scoring: sum is the one scoring there is")
    test, title = _text(source, top, "test"), _text(source, top, "title")
    sentences = _sentences(source, top["sentences"][1])
    items = _items(source, top["items"][1])
    bands = _bands(source, top["bands"][1], sum(i.max for i in items))
    code = _text(source, top, "language") if "language" in top else "en"
    try:
        lang.get(code)
    except DefinitionError as e:
        raise _err(source, top["language"][1], str(e)) from None
    items = tuple(replace(i, language=code) for i in items)
    return Definition(test, title, items, bands, sentences, source, code)


_Mapping, _Sequence = yaml.MappingNode, yaml.SequenceNode


def _err(source: str, node: Any, message: str) -> DefinitionError:
    return err(source, node, message, DefinitionError)


def _fields(
    source: str, node: Any, keys: tuple[str, ...], what: str, optional: tuple[str, ...] = ()
) -> dict[str, tuple[Any, Any]]:
    return fields(source, node, keys, what, optional, DefinitionError)


def _value(fields: dict[str, tuple[Any, Any]], key: str) -> Any:
    return scalar(fields[key][1])


def _text(source: str, fields: dict[str, tuple[Any, Any]], key: str) -> str:
    value = _value(fields, key)
    if not isinstance(value, str) or not value.strip():
        raise _err(source, fields[key][1], f"{key} must be a text")
    return value.strip()


def _sentences(source: str, node: Any) -> dict[str, str]:
    if not isinstance(node, _Mapping):
        raise _err(source, node, f"sentences maps {', '.join(SENTENCES)} to texts")
    fields = _fields(source, node, SENTENCES, "sentences: ")
    return {k: _text(source, fields, k) for k in SENTENCES}


def _items(source: str, node: Any) -> tuple[Item, ...]:
    if not isinstance(node, _Sequence) or not node.value:
        raise _err(source, node, "items is a list of the test's items, in order")
    items: list[Item] = []
    for item_node in node.value:
        if not isinstance(item_node, _Mapping):
            raise _err(source, item_node, "an item is a mapping with key, title, question, options")
        kind_node = mapping(item_node).get("kind", (None, None))[1]
        kind = "choose" if kind_node is None else scalar(kind_node)
        if not isinstance(kind, str) or kind not in KIND_KEYS:
            raise _err(source, kind_node, f"an item's kind is one of {', '.join(KINDS)}")
        keys = COMMON_KEYS + KIND_KEYS[kind]
        optional = OPTIONAL_KEYS.get(kind, ()) + (("kind",) if kind == "choose" else ())
        fields = _fields(
            source,
            item_node,
            keys + (() if kind == "choose" else ("kind",)),
            f"an item ({kind}): ",
            optional,
        )
        key = _text(source, fields, "key")
        if not key.isidentifier() or key != key.lower():
            raise _err(source, fields["key"][1], f"an item key is a lower-case name, got {key!r}")
        if key in {i.key for i in items}:
            raise _err(source, fields["key"][1], f"item {key!r} is listed twice")
        common = (key, _text(source, fields, "title"), _text(source, fields, "question"))
        if kind == "choose":
            items.append(Item(*common, options=_options(source, key, fields["options"][1])))
            continue
        shows = _texts(source, key, fields["shows"][1], "shows") if "shows" in fields else ()
        parts = _parts(source, key, fields["parts"][1]) if "parts" in fields else ()
        if kind == "serial":
            _serial_step(source, key, fields["parts"][1], parts)
        if kind == "touches":
            missing = [p.name for p in parts if p.keywords[0] not in (s.lower() for s in shows)]
            if missing:
                raise _err(
                    source, fields["shows"][1], f"{key}: shows lacks the target of {missing}"
                )
        most = 0
        if "points" in fields:
            most = _value(fields, "points")
            if isinstance(most, bool) or not isinstance(most, int) or most < 1:
                raise _err(source, fields["points"][1], f"{key}: points is a whole number >= 1")
        ask = _text(source, fields, "ask")
        items.append(Item(*common, kind=kind, parts=parts, shows=shows, ask=ask, most=most))
    return tuple(items)


def serial_numbers(item: Item) -> list[int]:
    """The numbers of a ``serial`` item, in order (each part's first word)."""
    return [int(p.keywords[0]) for p in item.parts]


def _serial_step(source: str, item: str, node: Any, parts: tuple[Part, ...]) -> None:
    firsts = [p.keywords[0] for p in parts]
    if len(parts) < 2 or not all(w.lstrip("-").isdigit() for w in firsts):
        raise _err(source, node, f"{item}: a serial item's parts are two numbers or more")
    numbers = [int(w) for w in firsts]
    steps = {b - a for a, b in zip(numbers, numbers[1:], strict=False)}
    if len(steps) != 1 or 0 in steps:
        raise _err(source, node, f"{item}: a serial item's numbers go by one step, got {numbers}")


def _texts(source: str, item: str, node: Any, what: str) -> tuple[str, ...]:
    values = scalar(node) if isinstance(node, _Sequence) else None
    if not values or not all(isinstance(v, str) and v.strip() for v in values):
        raise _err(source, node, f"{item}: {what} is a list of texts")
    return tuple(v.strip() for v in values)


def _parts(source: str, item: str, node: Any) -> tuple[Part, ...]:
    if not isinstance(node, _Sequence) or not node.value:
        raise _err(source, node, f"{item}: parts is a list of {{name, words}}")
    parts: list[Part] = []
    for part_node in node.value:
        if not isinstance(part_node, _Mapping):
            raise _err(source, part_node, f"{item}: a part is {{name, words}}")
        fields = _fields(source, part_node, PART_KEYS, f"{item}: a part: ")
        name = _text(source, fields, "name")
        words = _texts(source, item, fields["words"][1], f"{name}: words")
        for word in words:
            for placeholder in _PLACEHOLDER.findall(word):
                if placeholder not in PLACEHOLDERS:
                    raise _err(
                        source,
                        fields["words"][1],
                        f"{item}: {name}: unknown placeholder {{{placeholder}}}; "
                        f"the placeholders are {', '.join(PLACEHOLDERS)}",
                    )
        parts.append(Part(name, tuple(w.lower() for w in words), words[0].strip()))
    return tuple(parts)


def _options(source: str, item: str, node: Any) -> tuple[Option, ...]:
    if not isinstance(node, _Sequence) or len(node.value) < 2:
        raise _err(source, node, f"{item}: options is a list of at least two options")
    options: list[Option] = []
    for option_node in node.value:
        if not isinstance(option_node, _Mapping):
            raise _err(source, option_node, f"{item}: an option is {{points, text, says, words}}")
        fields = _fields(source, option_node, OPTION_KEYS, f"{item}: an option: ")
        points = _value(fields, "points")
        if isinstance(points, bool) or not isinstance(points, int) or points < 0:
            raise _err(source, fields["points"][1], f"{item}: points are a whole number >= 0")
        if points in {o.points for o in options}:
            raise _err(source, fields["points"][1], f"{item}: two options worth {points}")
        words = scalar(fields["words"][1]) if isinstance(fields["words"][1], _Sequence) else None
        if not words or not all(isinstance(w, str) and w.strip() for w in words):
            raise _err(source, fields["words"][1], f"{item}: words is a list of phrases")
        keywords = tuple(w.strip().lower() for w in words)
        text, says = _text(source, fields, "text"), _text(source, fields, "says")
        options.append(Option(points, text, says, keywords))
    return tuple(options)


def _bands(source: str, node: Any, max_total: int) -> tuple[tuple[int, int, str], ...]:
    if not isinstance(node, _Sequence) or not node.value:
        raise _err(source, node, "bands is a list of {name, min, max}")
    bands = []
    for band_node in node.value:
        fields = mapping(band_node) if isinstance(band_node, _Mapping) else {}
        if set(fields) != {"name", "min", "max"}:
            raise _err(source, band_node, "a band is {name, min, max}")
        low, high = _value(fields, "min"), _value(fields, "max")
        if not all(isinstance(v, int) and not isinstance(v, bool) for v in (low, high)):
            raise _err(source, band_node, "a band's min and max are whole numbers")
        bands.append((low, high, _text(source, fields, "name"), band_node))
    expected = 0
    for low, high, name, band_node in bands:
        if low != expected or high < low:
            raise _err(
                source, band_node, f"band {name!r}: bands cover 0 to {max_total} in order, once"
            )
        expected = high + 1
    if expected != max_total + 1:
        raise _err(
            source, node, f"the bands end at {expected - 1}, the items' total at {max_total}"
        )
    return tuple((low, high, name) for low, high, name, _ in bands)
