"""The recogniser's benchmark (scripts/bench.sh --only speech): answers synthesised with
espeak-ng in several voices, clean and in white noise at 20, 10 and 5 dB SNR and in babble at
10 dB, recognised with the search the asr node uses for the item (restricted) and, as the
baseline on the same audio, with the free language model; each understood as Speech would
(questionnaire/answers.py). Per item kind: the share understood right (the points the clean text
itself is worth, with a confidence at Speech's min_confidence or more); word accuracy of both
searches; their real-time factors (CPU time over audio time)."""

from __future__ import annotations

import json
import os
import subprocess
import time
from datetime import date
from pathlib import Path
from typing import Any

import numpy as np

from clarc_agents import definitions
from clarc_agents.asr.audio import RATE
from clarc_agents.asr.searches import FREE, Search, search_for
from clarc_agents.questionnaire.answers import understand
from clarc_agents.questionnaire.orientation import values
from clarc_agents.questionnaire.spoken import TENS, UNITS, words
from clarc_sim.devices.sound import RoomNoise, Voice, mixed, noise_level, speak, speech_rms

MIN_CONFIDENCE = 0.5  # Speech's default
VOICES = (
    Voice("en-us", 150, 50),
    Voice("en-gb", 130, 45),
    Voice("en-gb-scotland", 170, 40),
    Voice("en-us+f3", 140, 60),
    Voice("en-gb-x-rp", 120, 55),
)
CONDITIONS = (("clean", None, None), ("white", "white", 20.0), ("white", "white", 10.0))
CONDITIONS += (("white", "white", 5.0), ("babble", "babble", 10.0))
ORDINAL = ("first", "second", "third", "fourth")


def _spelt(n: int) -> str:
    """A number under 101 in words, as people say it (spoken.py's words, the other way)."""
    units = {v: w for w, v in UNITS.items()}
    tens = {v: w for w, v in TENS.items()}
    if n == 100:
        return "one hundred"
    if n < 20:
        return units[n]
    return tens[n - n % 10] + ("" if n % 10 == 0 else " " + units[n % 10])


def serial_answers() -> list[str]:
    """Serial sevens as patients give them: 1 to 5 numbers, right or with one slip (the next
    numbers then follow from the slip, as the instrument scores them), plain and narrated
    ("minus seven is ..."), a few with hesitations."""
    out = []
    for length in range(1, 6):
        for slip in range(length + 1):  # slip == length: no slip
            given, previous = [], 100
            for k in range(length):
                previous = previous - 7 + (1 if k == slip else 0)
                given.append(previous)
            spoken = [_spelt(n) for n in given]
            out.append(", ".join(spoken))
            out.append("one hundred minus seven is " + ", minus seven is ".join(spoken))
    out += [
        "um, ninety three, I think eighty six, seventy nine",
        "ninety three, uh, eighty six",
        "one hundred take away seven, ninety three, take away seven, eighty six",
        "ninety, eighty, seventy",
        "ninety three, eighty three, seventy three",
        "I don't know",
    ]
    return out


# (item, what is said) for the words items: right, partly right, wrong, hedged, unknown
WORDS = {
    "registration": (
        "apple, table, penny",
        "apple and penny",
        "table, penny",
        "apple",
        "penny, apple, table",
        "apple, banana, penny",
        "a car, a dog and a table",
        "I don't know",
    ),
    "recall": (
        "apple, table, penny",
        "apple and table",
        "penny",
        "table and penny",
        "apple, orange",
        "a chair, a penny",
        "I don't remember",
        "table, apple, penny",
    ),
    "naming": (
        "a pencil and a watch",
        "pencil, watch",
        "a pen and a clock",
        "a pencil",
        "a watch",
        "a wristwatch and a pencil",
        "scissors",
        "a pen or a pencil",
    ),
    "orientation_place": (
        "Spain, Seville, first floor",
        "Spain, Andalusia, Seville, the hospital, the first floor",
        "Seville",
        "France, Paris",
        "the hospital, the second floor",
        "Spain or Portugal",
    ),
    "orientation_time": (
        "twenty twenty six, winter, the first of December, Tuesday, December",
        "two thousand and twenty six, winter, December the first, Tuesday",
        "twenty twenty five, autumn, the second, Monday, November",
        "Monday or Tuesday",
        "it is December",
        "winter, Tuesday",
        "I don't know",
    ),
    "repetition": ("no ifs, ands, or buts", "no ifs and buts", "no buts", "if and but"),
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
    out += [("serial", mmse.item("attention"), said) for said in serial_answers()]
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
    # per kind: {search: [word errors, reference words]}
    words_right: dict[str, dict[str, list[int]]] = {}
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
                # the baseline, free decoding of the same audio (a sample of the choose answers,
                # every serial and words one: it is slow)
                sampled = kind != "choose" or seed % (8 if quick else 4) == 0
                if snr in (None, 20.0) and sampled:
                    started = time.process_time()
                    baseline = recogniser.hear(audio, free)
                    rtf["free"][0] += time.process_time() - started
                    rtf["free"][1] += len(audio) / RATE
                    reference = words(said)
                    for which, text in (("restricted", heard.text), ("free", baseline.text)):
                        errors = words_right.setdefault(kind, {}).setdefault(which, [0, 0])
                        errors[0] += _word_errors(reference, words(text))
                        errors[1] += len(reference)
        by_condition[name] = {
            k: {"right": r, "of": n, "share": r / n} for k, (r, n) in counts.items()
        }
        out["answers_per_condition"] = sum(n for _, n in counts.values())
    out["understood"] = by_condition
    out["word_accuracy"] = {
        kind: {k: {"share": 1 - e / max(n, 1), "reference_words": n} for k, (e, n) in s.items()}
        for kind, s in words_right.items()
    }
    out["real_time_factor"] = {k: cpu / max(audio, 1e-9) for k, (cpu, audio) in rtf.items()}
    return out


def table(speech: dict[str, Any]) -> list[str]:
    if "understood" not in speech:  # the loop alone (--only speech_loop)
        return _loop_lines(speech.get("loop"))
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
    for kind in sorted(wa):
        lines.append(
            f"  word accuracy ({kind}, clean and 20 dB): restricted "
            f"{wa[kind]['restricted']['share']:.1%}, free model (baseline) "
            f"{wa[kind]['free']['share']:.1%} of {wa[kind]['free']['reference_words']} words"
        )
    lines.append(
        f"  real-time factor: restricted {rtf['restricted']:.3f}, free model {rtf['free']:.3f}"
    )
    return lines + _loop_lines(speech.get("loop"))


def _loop_lines(loop: dict[str, Any] | None) -> list[str]:
    if not loop:
        return []
    if "error" in loop:
        return [f"  end of speech to the answer in the DSR: {loop['error']}"]
    d = loop["end_of_speech_to_dsr_ms"]
    return [
        f"  end of speech to the answer in the DSR ({loop['answers']} answers, --audio): "
        f"p50 {d['p50_ms']:.0f} ms, p99 {d['p99_ms']:.0f} ms"
    ]


LOOP_SCENARIOS = ("default.yaml", "mmse_normal.yaml")  # a Barthel, then a Mini-Mental


def bench_speech_loop(work: Path, domain: int, root: Path) -> dict[str, Any]:
    """End of speech to the answer in the DSR, through the whole loop with sound: the default
    Barthel scenario and the normal Mini-Mental, each run by scripts/launch.sh --audio (patient
    en-gb at 25 dB SNR of white noise, the robot at 300 words a minute, pace 0.7) and recorded
    to MCAP. For each hypothesis the asr node published (clarc/asr: its text and the capture
    time its speech ended) whose text Speech stored as an answer or as not understood, the time
    from that end to the recorder receiving the DSR delta that holds it: what any agent of the
    DSR sees."""
    delays: list[float] = []
    unmatched = 0
    per_scenario = {}
    for name in LOOP_SCENARIOS:
        run = _speech_loop_run(work, domain, root, name)
        if "error" in run:
            return {"error": f"{name}: {run['error']}"}
        delays += run["delays"]
        unmatched += run["unmatched"]
        per_scenario[name] = len(run["delays"])
    p50, p99 = np.percentile(delays, [50, 99])
    return {
        "answers": len(delays),
        "answers_per_scenario": per_scenario,
        "hypotheses_not_stored": unmatched,
        "end_of_speech_to_dsr_ms": {"p50_ms": 1000 * p50, "p99_ms": 1000 * p99},
        "delays_ms": [round(1000 * d, 1) for d in delays],
    }


def _speech_loop_run(work: Path, domain: int, root: Path, name: str) -> dict[str, Any]:
    from dsr_graph.formats.mcap_recording import dsr_channels, messages

    tag = Path(name).stem
    scenario = work / f"aloud_{tag}.yaml"
    text = (root / "scenarios" / name).read_text()
    sound = "voice: {name: en-gb, rate: 160, pitch: 40}\nroom: {noise: white, snr_db: 25}\n"
    text = text.replace("items:", sound + "items:", 1) if "items:" in text else text + sound
    scenario.write_text(text)
    recording = work / f"aloud_{tag}.mcap"
    argv = [str(root / "scripts" / "launch.sh"), "--scenario", str(scenario), "--audio"]
    argv += ["--scale", "0.7", "--voice-rate", "300", "--timeout", "900"]
    argv += ["--db", str(work / f"aloud_{tag}.sqlite"), "--run-dir", str(work / f"run_{tag}")]
    argv += ["--viewer-port", "0", "--dashboard-port", "0", "--record", str(recording)]
    env = dict(os.environ, ROS_DOMAIN_ID=str(domain))
    run = subprocess.run(argv, capture_output=True, text=True, env=env, timeout=1000)
    if run.returncode != 0:
        return {"error": f"launch.sh exited {run.returncode}: {run.stderr[-2000:]}"}
    deltas = dsr_channels(recording)["deltas"]
    pending: list[tuple[str, float]] = []  # (the JSON of what Speech stores, end of speech)
    delays, unmatched = [], 0
    for m in messages(recording, ["/clarc/asr", deltas]):
        if m.topic == "/clarc/asr":
            said = json.loads(m.message.data)
            # Speech takes one hypothesis at a time: one not stored before the next came was
            # ignored (heard while no answer was awaited), and must not match a later answer
            unmatched += len(pending)
            pending = [(json.dumps(said["text"]), float(said["end"]))]
            continue
        for i, (stored, end) in enumerate(pending):
            if stored in m.message.data:
                delays.append(m.log_time / 1e9 - end)
                del pending[i]
                break
    if not delays:
        return {"error": "no hypothesis was found stored in the DSR"}
    return {"delays": delays, "unmatched": unmatched + len(pending)}
