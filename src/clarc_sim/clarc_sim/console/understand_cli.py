"""``clarc understand TEST ITEM "text" [--json]``: how a text is understood and scored for an item
of a test definition, exactly as the Speech agent (or, for the shapes of a ``touches`` item,
the Panel agent) understands it: the points, what was credited and why the rest was not.

TEST is a shipped test (barthel, mmse, lawton) or a definition file (format: docs/FORMAT.md),
in ``--language`` (default en; a definition file says its own); orientation is scored against
``--date`` (default today) and ``--place`` (PELEA's ``place``).
With ``--json``: one object, ``text``, ``words`` (the text as it is matched), ``understood``
("answer", "skip", "not_understood"), ``points`` (null when nothing in it is an answer),
``max``, ``matched``, ``why``.
"""

from __future__ import annotations

import argparse
import json
import sys
from datetime import date
from pathlib import Path

from clarc_agents import definitions, languages
from clarc_agents.exceptions import DefinitionError
from clarc_agents.questionnaire.answers import Understanding, touched_in_order, understand
from clarc_agents.questionnaire.orientation import DEFAULT_PLACE, values
from clarc_agents.questionnaire.spoken import words


def add_parser(sub) -> None:
    p = sub.add_parser("understand", help="how a text is understood for an item of a test")
    p.add_argument("test", help=f"a shipped test ({', '.join(definitions.tests())}) or a file")
    p.add_argument("item", help="the item's key")
    p.add_argument("text", help="what was said (for a touches item: the shapes, in order)")
    p.add_argument("--json", action="store_true", help="one JSON object")
    p.add_argument(
        "--language",
        default=None,
        help=f"the test's language ({', '.join(languages.codes())}); default en",
    )
    p.add_argument(
        "--date", type=date.fromisoformat, default=None, help="orientation's date (today)"
    )
    p.add_argument(
        "--place",
        nargs=5,
        metavar=("COUNTRY", "PROVINCE", "CITY", "BUILDING", "FLOOR"),
        default=list(DEFAULT_PLACE),
        help="orientation's place, each part's ways of saying it joined by '|'",
    )
    p.set_defaults(run=run)


def definition_of(test: str, language: str | None = None) -> definitions.Definition:
    if test in definitions.tests():
        return definitions.load(test, language or "en")
    path = Path(test)
    if not path.is_file():
        shipped = ", ".join(definitions.tests())
        raise DefinitionError(f"{test!r} is neither a shipped test ({shipped}) nor a file")
    definition = definitions.parse(path.read_text(encoding="utf-8"), str(path))
    if language not in (None, definition.language):
        raise DefinitionError(f"{path} is in {definition.language!r}, not {language!r}")
    return definition


def explain(
    test: str, key: str, text: str, today: date, place, language: str | None = None
) -> dict:
    """What ``clarc understand`` prints, as a dict."""
    definition = definition_of(test, language)
    definition = definition.filled(values(today, place, definition.language))
    keys = [i.key for i in definition.items]
    if key not in keys:
        raise DefinitionError(
            f"{definition.test} has no item {key!r}; its items: {', '.join(keys)}"
        )
    item = definition.item(key)
    if item.kind in ("drawing", "eyes"):
        how = "a drawing, scored by a clinician" if item.kind == "drawing" else "the camera"
        raise DefinitionError(f"{definition.test}'s {key} is answered by {how}, not in words")
    if item.kind == "touches":
        shapes = [s for s in words(text, item.language) if s != "and"]
        points = touched_in_order(item, shapes)
        meaning = Understanding("answer", points, tuple(shapes))
    else:
        meaning = understand(item, text)
    return {
        "test": definition.test,
        "item": key,
        "kind": item.kind,
        "text": text,
        "language": item.language,
        "words": words(text, item.language),
        "understood": meaning.kind,
        "points": meaning.points if meaning.kind == "answer" else None,
        "max": item.max,
        "matched": list(meaning.matched),
        "why": list(meaning.why),
    }


def run(args: argparse.Namespace) -> int:
    try:
        today = args.date or date.today()
        out = explain(args.test, args.item, args.text, today, args.place, args.language)
    except (DefinitionError, OSError) as e:
        print(f"clarc understand: {e}", file=sys.stderr)
        return 1
    if args.json:
        print(json.dumps(out))
        return 0
    worth = "no answer" if out["points"] is None else f"{out['points']} of {out['max']} points"
    print(f"{out['test']} {out['item']} ({out['kind']}): {out['understood']}, {worth}")
    print(f"  heard as: {' '.join(out['words'])}")
    if out["matched"]:
        label = {"serial": "numbers given", "touches": "touched"}.get(out["kind"], "credited")
        print(f"  {label}: {', '.join(out['matched'])}")
    for reason in out["why"]:
        print(f"  not credited: {reason}")
    return 0
