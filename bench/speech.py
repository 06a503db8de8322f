"""The recogniser's benchmark (scripts/bench.sh --only speech): answers synthesised with
espeak-ng in several voices, clean and in white noise at 20, 10 and 5 dB SNR and in babble at
10 dB, recognised with the search the asr node uses for the item (restricted) and, as the
baseline on the same audio, with the free language model; each understood as Speech would
(questionnaire/answers.py). Per item kind: the share understood right (the points the clean text
itself is worth, with a confidence at Speech's min_confidence or more); word accuracy of both
searches; their real-time factors (CPU time over audio time)."""

from __future__ import annotations

import time
from datetime import date
from typing import Any

import numpy as np

from clarc_agents import definitions
from clarc_agents.asr.audio import RATE
from clarc_agents.asr.searches import FREE, Search, search_for
from clarc_agents.questionnaire.answers import understand
from clarc_agents.questionnaire.orientation import values
from clarc_agents.questionnaire.spoken import words
from clarc_sim.devices.sound import RoomNoise, Voice, mixed, noise_level, speak, speech_rms

MIN_CONFIDENCE = 0.5  # Speech's default
VOICES = (
    Voice("en-us", 150, 50),
    Voice("en-gb", 130, 45),
    Voice("en-gb-scotland", 170, 40),
    Voice("en-us+f3", 140, 60),
)
CONDITIONS = (("clean", None, None), ("white", "white", 20.0), ("white", "white", 10.0))
CONDITIONS += (("white", "white", 5.0), ("babble", "babble", 10.0))
ORDINAL = ("first", "second", "third", "fourth")
SERIAL = (
    "ninety three, eighty six, seventy nine, seventy two, sixty five",
    "ninety three, eighty five, seventy eight",
    "one hundred minus seven is ninety three, minus seven is eighty six",
)
WORDS = {
    "registration": ("apple, table, penny", "apple and penny"),
    "naming": ("a pencil and a watch", "a pencil"),
    "orientation_place": ("Spain, Seville, first floor",),
}


def answers() -> list[tuple[str, Any, str]]:
    """(kind, item, what is said) for every answer of the benchmark."""
    out = []
    for test in ("barthel", "lawton"):
        for item in definitions.load(test).items:
            for n, option in enumerate(item.options, 1):
                out.append(("choose", item, option.says))
                out.append(("choose", item, f"option {('one', 'two', 'three', 'four')[n - 1]}"))
                out.append(("choose", item, f"the {ORDINAL[n - 1]} one"))
    mmse = definitions.load("mmse").filled(values(date(2026, 12, 1)))
    out += [("serial", mmse.item("attention"), said) for said in SERIAL]
    out += [("words", mmse.item(key), said) for key, phrases in WORDS.items() for said in phrases]
    return out


def _heard_audio(text: str, voice: Voice, noise: str | None, snr: float | None, seed: int):
    speech = speak(text, voice).astype(float)
    pad = np.zeros(RATE // 2)
    signal = np.concatenate([pad, speech, pad])
    if noise is not None:
        signal = signal + RoomNoise(noise, noise_level(speech_rms(speech), snr), seed).read(
            len(signal)
        )
    return mixed([signal])


def _word_errors(reference: list[str], hypothesis: list[str]) -> int:
    """Levenshtein distance over words."""
    row = list(range(len(hypothesis) + 1))
    for i, r in enumerate(reference, 1):
        previous, row[0] = row[0], i
        for j, h in enumerate(hypothesis, 1):
            previous, row[j] = row[j], min(row[j] + 1, row[j - 1] + 1, previous + (r != h))
    return row[-1]


def bench_speech(quick: bool) -> dict[str, Any]:
    from clarc_agents.asr.recogniser import Recogniser

    recogniser = Recogniser()
    voices = VOICES[:2] if quick else VOICES
    cases = answers()
    if quick:
        cases = cases[::3]
    free = Search(FREE, None)
    out: dict[str, Any] = {"voices": [v.name for v in voices], "answers_per_condition": 0}
    rtf = {"restricted": [0.0, 0.0], "free": [0.0, 0.0]}  # CPU s, audio s
    words_right = {"restricted": [0, 0], "free": [0, 0]}  # word errors, reference words
    by_condition: dict[str, dict[str, list[int]]] = {}
    seed = 0
    for label, noise, snr in CONDITIONS:
        name = label if snr is None else f"{label} {snr:g} dB"
        counts: dict[str, list[int]] = {}
        for kind, item, said in cases:
            truth = understand(item, said)
            search = search_for(item, recogniser.known) or free
            for voice in voices:
                seed += 1
                audio = _heard_audio(said, voice, noise, snr, seed)
                started = time.process_time()
                heard = recogniser.hear(audio, search)
                cpu = time.process_time() - started
                rtf["restricted"][0] += cpu
                rtf["restricted"][1] += len(audio) / RATE
                meaning = understand(item, heard.text)
                right = (
                    meaning.kind == truth.kind == "answer"
                    and meaning.points == truth.points
                    and heard.confidence >= MIN_CONFIDENCE
                )
                tally = counts.setdefault(kind, [0, 0])
                tally[0] += right
                tally[1] += 1
                # the baseline, free decoding of the same audio (a sample: it is slow)
                if kind == "choose" and snr in (None, 20.0) and seed % (8 if quick else 4) == 0:
                    started = time.process_time()
                    baseline = recogniser.hear(audio, free)
                    rtf["free"][0] += time.process_time() - started
                    rtf["free"][1] += len(audio) / RATE
                    reference = words(said)
                    for which, text in (("restricted", heard.text), ("free", baseline.text)):
                        words_right[which][0] += _word_errors(reference, words(text))
                        words_right[which][1] += len(reference)
        by_condition[name] = {
            k: {"right": r, "of": n, "share": r / n} for k, (r, n) in counts.items()
        }
        out["answers_per_condition"] = sum(n for _, n in counts.values())
    out["understood"] = by_condition
    out["word_accuracy"] = {
        k: {"share": 1 - e / max(n, 1), "reference_words": n} for k, (e, n) in words_right.items()
    }
    out["real_time_factor"] = {k: cpu / max(audio, 1e-9) for k, (cpu, audio) in rtf.items()}
    out["not_measured"] = "end of speech to the answer in the DSR (needs the whole loop)"
    return out


def table(speech: dict[str, Any]) -> list[str]:
    lines = [
        f"speech: {speech['answers_per_condition']} answers a condition, voices "
        f"{', '.join(speech['voices'])}; understood right (restricted search)"
    ]
    kinds = sorted({k for c in speech["understood"].values() for k in c})
    lines.append("  condition        " + "".join(f"{k:>16}" for k in kinds))
    for condition, counts in speech["understood"].items():
        cells = "".join(
            f"{counts[k]['right']:>6}/{counts[k]['of']:<4} {counts[k]['share']:4.0%}" for k in kinds
        )
        lines.append(f"  {condition:<16} {cells}")
    wa, rtf = speech["word_accuracy"], speech["real_time_factor"]
    lines.append(
        f"  word accuracy (choose, clean and 20 dB): restricted {wa['restricted']['share']:.1%}, "
        f"free model (baseline) {wa['free']['share']:.1%} of {wa['free']['reference_words']} words"
    )
    lines.append(
        f"  real-time factor: restricted {rtf['restricted']:.3f}, free model {rtf['free']:.3f}"
    )
    return lines
