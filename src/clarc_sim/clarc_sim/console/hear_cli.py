"""``clarc hear FILE [--test TEST --item ITEM] [--language es] [--recogniser R] [--json]``: the
recogniser the ``asr`` node runs (Whisper unless ``--recogniser pocketsphinx``; the
multilingual Whisper base for a test in Spanish), on a recording (WAV, PCM 16
bit, at 8, 16, 22.05 or 44.1 kHz or any other rate, resampled with soxr; or raw 16 kHz PCM 16
bit, ``.raw``), biased as the node biases it while that item's answer is awaited (nothing
expected without ``--item``), and how the text is understood for the item (``clarc
understand``). With ``--json``: one object with ``text``, ``confidence``, ``start`` and ``end``
(seconds into the file), ``recogniser``, ``search`` (how it was heard: Whisper's ``prompted``,
``rescored`` or ``free``; pocketsphinx's ``grammar``, ``vocabulary`` or ``free``),
``transcript`` when rescored (what free decoding wrote), and with an item ``understood`` and
``points`` (null when nothing in it is an answer). What is heard with a confidence under
Speech's ``min_confidence`` (0.5) is not understood by the robot: ``points`` is then null too,
and ``sure`` false.
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from datetime import date

from clarc_agents import languages
from clarc_agents.asr.audio import RATE, read_audio
from clarc_agents.asr.expectations import expectation_for
from clarc_agents.asr.hearing import DEFAULT, MIN_CONFIDENCE, RECOGNISERS, open_recogniser
from clarc_agents.exceptions import AudioError, DefinitionError, ModelError
from clarc_agents.questionnaire.orientation import DEFAULT_PLACE, values
from clarc_sim.console.understand_cli import definition_of, explain


def add_parser(sub) -> None:
    p = sub.add_parser("hear", help="what the recogniser hears in a recording")
    p.add_argument("file", help="a WAV file (16-bit PCM, any rate) or raw 16 kHz PCM (.raw)")
    p.add_argument("--test", help="a shipped test or a definition file (with --item)")
    p.add_argument("--item", help="the item whose answer is awaited: restricts the search")
    p.add_argument(
        "--recogniser", choices=RECOGNISERS, default=DEFAULT, help="default: %(default)s"
    )
    p.add_argument("--json", action="store_true", help="one JSON object")
    p.add_argument("--date", type=date.fromisoformat, default=None, help="orientation's date")
    p.add_argument(
        "--language",
        choices=languages.codes(),
        default=None,
        help="the test's language (a shipped test's; default en): Spanish is heard by the "
        "multilingual Whisper base",
    )
    p.set_defaults(run=run)


def hear(
    path: str,
    test: str | None,
    key: str | None,
    today: date,
    recogniser: str = DEFAULT,
    language: str | None = None,
) -> dict:
    """What ``clarc hear`` prints, as a dict."""
    if (test is None) != (key is None):
        raise DefinitionError("--test and --item go together")
    samples = read_audio(path)
    item = None
    if key is not None:
        definition = definition_of(test, language)
        definition = definition.filled(values(today, DEFAULT_PLACE, definition.language))
        language = definition.language
        keys = [i.key for i in definition.items]
        if key not in keys:
            raise DefinitionError(f"{definition.test} has no item {key!r}; its items: {keys}")
        item = definition.item(key)
        if expectation_for(item) is None:
            raise DefinitionError(f"{definition.test}'s {key} is not answered by voice")
    try:
        hearing = open_recogniser(recogniser, language or "en")  # loads the model: only now
    except ValueError as e:
        raise DefinitionError(str(e)) from None
    started = time.process_time()
    heard, how = hearing.hear_item(samples, item)
    cpu = time.process_time() - started
    out = {
        "file": path,
        "text": heard.text,
        "confidence": round(heard.confidence, 3),
        "start": round(heard.start, 3),
        "end": round(heard.end, 3),
        "recogniser": hearing.name,
        "search": how,
        "real_time_factor": round(cpu / (len(samples) / RATE), 3),
    }
    if heard.transcript:
        out["transcript"] = heard.transcript
    if heard.confirmed_by:
        out["confirmed_by"] = heard.confirmed_by
    if heard.snr_db is not None:
        out["snr_db"] = round(heard.snr_db, 1)
    if key is not None:
        understood = explain(test, key, heard.text, today, DEFAULT_PLACE, language)
        out |= {k: understood[k] for k in ("test", "item", "understood", "points", "max")}
        out["sure"] = heard.confidence >= MIN_CONFIDENCE
        if not out["sure"]:  # the robot would ask again: no points from it
            out |= {"understood": "not_understood", "points": None}
    return out


def run(args: argparse.Namespace) -> int:
    try:
        today = args.date or date.today()
        out = hear(args.file, args.test, args.item, today, args.recogniser, args.language)
    except (AudioError, DefinitionError, ModelError, OSError) as e:
        print(f"clarc hear: {e}", file=sys.stderr)
        return 1
    if args.json:
        print(json.dumps(out))
        return 0
    text = out["text"] or "(nothing)"
    how = f"{out['recogniser']}, {out['search']}"
    if "snr_db" in out:
        how += f", the voice {out['snr_db']:g} dB over the room"
    print(f"heard: {text}  (confidence {out['confidence']:.2f}, {how})")
    if "transcript" in out:
        print(f"  (free decoding wrote: {out['transcript'] or '(nothing)'})")
    if "confirmed_by" in out:
        print(f"  (pocketsphinx heard the same answer: {out['confirmed_by']})")
    if "item" in out:
        worth = "no answer" if out["points"] is None else f"{out['points']} of {out['max']} points"
        print(f"{out['test']} {out['item']}: {out['understood']}, {worth}")
    return 0
