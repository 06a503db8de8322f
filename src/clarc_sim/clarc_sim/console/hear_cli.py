"""``clarc hear FILE [--test TEST --item ITEM] [--json]``: the recogniser the ``asr`` node runs,
on a recording (WAV, PCM 16 bit, at 8, 16, 22.05 or 44.1 kHz or any other rate, resampled with
soxr; or raw 16 kHz PCM 16 bit, ``.raw``), with the search the node would use while that item's
answer is awaited (the free language model without ``--item``), and how the text is understood
for the item (``clarc understand``). With ``--json``: one object with ``text``, ``confidence``,
``start`` and ``end`` (seconds into the file), ``search`` (``grammar`` or ``free``), and with an
item ``understood`` and ``points`` (null when nothing in it is an answer).
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from datetime import date

from clarc_agents.asr.audio import RATE, read_audio
from clarc_agents.asr.searches import FREE, Search, search_for
from clarc_agents.exceptions import AudioError, DefinitionError
from clarc_agents.questionnaire.orientation import DEFAULT_PLACE, values
from clarc_sim.console.understand_cli import definition_of, explain


def add_parser(sub) -> None:
    p = sub.add_parser("hear", help="what the recogniser hears in a recording")
    p.add_argument("file", help="a WAV file (16-bit PCM, any rate) or raw 16 kHz PCM (.raw)")
    p.add_argument("--test", help="a shipped test or a definition file (with --item)")
    p.add_argument("--item", help="the item whose answer is awaited: restricts the search")
    p.add_argument("--json", action="store_true", help="one JSON object")
    p.add_argument("--date", type=date.fromisoformat, default=None, help="orientation's date")
    p.set_defaults(run=run)


def hear(path: str, test: str | None, key: str | None, today: date) -> dict:
    """What ``clarc hear`` prints, as a dict."""
    from clarc_agents.asr.recogniser import Recogniser  # loads the model: only when hearing

    if (test is None) != (key is None):
        raise DefinitionError("--test and --item go together")
    samples = read_audio(path)
    recogniser = Recogniser()
    search = Search(FREE, None)
    if key is not None:
        definition = definition_of(test).filled(values(today, DEFAULT_PLACE))
        keys = [i.key for i in definition.items]
        if key not in keys:
            raise DefinitionError(f"{definition.test} has no item {key!r}; its items: {keys}")
        search = search_for(definition.item(key), recogniser.known)
        if search is None:
            raise DefinitionError(f"{definition.test}'s {key} is not answered by voice")
    started = time.process_time()
    heard = recogniser.hear(samples, search)
    cpu = time.process_time() - started
    out = {
        "file": path,
        "text": heard.text,
        "confidence": round(heard.confidence, 3),
        "start": heard.start,
        "end": heard.end,
        "search": search.kind,
        "real_time_factor": round(cpu / (len(samples) / RATE), 3),
    }
    if key is not None:
        understood = explain(test, key, heard.text, today, DEFAULT_PLACE)
        out |= {k: understood[k] for k in ("test", "item", "understood", "points", "max")}
    return out


def run(args: argparse.Namespace) -> int:
    try:
        out = hear(args.file, args.test, args.item, args.date or date.today())
    except (AudioError, DefinitionError, OSError) as e:
        print(f"clarc hear: {e}", file=sys.stderr)
        return 1
    if args.json:
        print(json.dumps(out))
        return 0
    text = out["text"] or "(nothing)"
    print(f"heard: {text}  (confidence {out['confidence']:.2f}, {out['search']} search)")
    if "item" in out:
        worth = "no answer" if out["points"] is None else f"{out['points']} of {out['max']} points"
        print(f"{out['test']} {out['item']}: {out['understood']}, {worth}")
    return 0
