"""The recognisers' benchmark (scripts/bench.sh --only speech): answers synthesised with
espeak-ng in several voices, clean and in white noise at 20, 10 and 5 dB SNR and in babble at
10 dB, heard by each recogniser (Whisper, pocketsphinx) as the asr node hears them while the
item's answer is awaited, each understood as Speech would (questionnaire/answers.py). Per
recogniser, condition and item kind: the share understood right (the points the clean text
itself is worth, with a confidence at Speech's min_confidence or more), the share scored wrong
(understood and sure, but another score) and the share sent to the clinician (the rest); the
real speakers of ../shared/data/speech; real-time factors (CPU time over audio time)."""

from __future__ import annotations

import json
import os
import subprocess
import time
from dataclasses import replace
from datetime import date
from pathlib import Path
from typing import Any

import numpy as np

from clarc_agents import definitions
from clarc_agents.asr.audio import RATE
from clarc_agents.asr.hearing import CONFIRM_CONFIDENCE, MIN_CONFIDENCE
from clarc_agents.questionnaire.agreement import KINDS, heard_again
from clarc_agents.questionnaire.answers import understand
from clarc_agents.questionnaire.orientation import values
from clarc_agents.questionnaire.spoken import TENS, UNITS
from clarc_sim.devices.sound import RoomNoise, Voice, mixed, noise_level, speak, speech_rms

ROOT = Path(__file__).resolve().parents[1]
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


RECOGNISERS = ("whisper", "pocketsphinx")
AGAIN_SEEDS = 1_000_000  # the noise of the answers said again
OUTCOMES = ("right", "wrong", "clinician")


def _outcome(item, truth, heard) -> str:
    """How an answer ends for the robot: ``right`` (understood, sure, the points the words are
    worth), ``wrong`` (understood and sure, but another score: the dangerous one) or
    ``clinician`` (not understood or not sure: asked again, in the end the clinician's)."""
    meaning = understand(item, heard.text)
    if heard.confidence < MIN_CONFIDENCE or meaning.kind == "not_understood":
        return "clinician"
    right = meaning.kind == truth.kind and meaning.points == truth.points
    return "right" if right else "wrong"


def _over_the_dialogue(recogniser, item, truth, heard, said_again) -> tuple[str, str]:
    """How an answer ends without and with the dialogue's repair: a choose answer read back
    when not sure; a words or serial answer asked again when not sure and said again
    (``said_again``: the text, the voice made 10% slower, the noise and its own seed)."""
    if item.kind not in KINDS:
        return _outcome(item, truth, heard), _read_back(item, truth, heard)
    second = None
    if _outcome(item, truth, heard) == "clinician":
        said, voice, noise, snr, seed = said_again
        slower = replace(voice, words_per_minute=int(voice.words_per_minute * 0.9))
        second, _ = recogniser.hear_item(_heard_audio(said, slower, noise, snr, seed), item)
    return _asked_again(item, truth, heard, second)


def _asked_again(item, truth, first, second) -> tuple[str, str]:
    """How a words or serial answer ends over two windows, the patient asked again when the
    first was not sure (``second``: what was heard then, None when the first was): without and
    with Speech taking the same answer heard twice (questionnaire/agreement.py)."""
    if second is None:
        outcome = _outcome(item, truth, first)
        return outcome, outcome
    without = _outcome(item, truth, second)
    if without != "clinician":
        return without, without
    again = heard_again(item, [(first.text, first.confidence)], second.text, second.confidence)
    if again is None or again[0] < MIN_CONFIDENCE:
        return without, without
    return without, _outcome(item, truth, replace(second, confidence=again[0]))


def _read_back(item, truth, heard) -> str:
    """How a choose answer ends with Speech's read-back: an option heard from
    ``CONFIRM_CONFIDENCE`` up to ``MIN_CONFIDENCE`` is read back and the patient's yes counts
    it; a wrong option read back is denied and asked again, counted here as not right."""
    outcome = _outcome(item, truth, heard)
    meaning = understand(item, heard.text)
    if outcome != "clinician" or heard.confidence < CONFIRM_CONFIDENCE or meaning.kind != "answer":
        return outcome
    return "right" if meaning.points == truth.points else "clinician"


def _tally(counts: dict[str, list[int]]) -> dict[str, Any]:
    return {
        kind: {"of": sum(c), **{o: n / max(sum(c), 1) for o, n in zip(OUTCOMES, c, strict=True)}}
        for kind, c in counts.items()
    }


def real_speakers(speech_dir: Path, recogniser) -> dict[str, Any]:
    """../shared's Free Spoken Digit Dataset speakers saying one, two or three to a Barthel
    item of three options (8 kHz, resampled): real voices the benchmark never synthesised."""
    from clarc_agents.asr.audio import read_audio

    item = definitions.load("barthel").item("feeding")
    counts = {"choose": [0, 0, 0]}
    for path in sorted((speech_dir / "fsdd").glob("[123]_*.wav")):
        truth = understand(item, ("one", "two", "three")[int(path.name[0]) - 1])
        heard, _ = recogniser.hear_item(read_audio(path), item)
        counts["choose"][OUTCOMES.index(_outcome(item, truth, heard))] += 1
    return _tally(counts)["choose"]


def bench_speech(quick: bool) -> dict[str, Any]:
    """Each recogniser (RECOGNISERS) on the same synthesised audio, each answer understood as
    Speech would: per condition and item kind, the share right, wrong and sent to the
    clinician; the real-time factor (CPU time over audio time) and the wall time an answer."""
    from clarc_agents.asr.hearing import open_recogniser

    voices = VOICES[:2] if quick else VOICES
    cases = answers()
    if quick:
        cases = cases[::3]
    out: dict[str, Any] = {
        "voices": [v.name for v in voices],
        "answers_per_condition": len(cases) * len(voices),
        "recognisers": {},
    }
    speech_dir = ROOT.parent / "shared" / "data" / "speech"
    for name in RECOGNISERS:
        recogniser = open_recogniser(name)
        cpu = audio_s = wall = 0.0
        answered = 0
        by_condition: dict[str, Any] = {}
        # Whisper tiny.en's answers without the other opinions (pocketsphinx's, Whisper base's):
        # those another confirmed were not sure before it (second_opinion.py), so the same run
        # tells both
        alone: dict[str, Any] = {}
        # over the dialogue: what the repair adds (the read-back of a choose answer not sure;
        # a words or serial answer asked again, said again in a second rendition: the voice
        # 10% slower, other noise, and taken when heard the same, questionnaire/agreement.py)
        dialogue: dict[str, Any] = {}
        seed = 0
        for label, noise, snr in CONDITIONS:
            condition = label if snr is None else f"{label} {snr:g} dB"
            counts: dict[str, list[int]] = {}
            counts_alone: dict[str, list[int]] = {}
            twice: tuple[dict[str, list[int]], ...] = ({}, {})  # without, with the repair
            for kind, item, said in cases:
                truth = understand(item, said)
                for voice in voices:
                    seed += 1
                    audio = _heard_audio(said, voice, noise, snr, seed)
                    started, clock = time.process_time(), time.perf_counter()
                    heard, how = recogniser.hear_item(audio, item)
                    cpu += time.process_time() - started
                    wall += time.perf_counter() - clock
                    audio_s += len(audio) / RATE
                    answered += 1
                    outcome = _outcome(item, truth, heard)
                    counts.setdefault(kind, [0, 0, 0])[OUTCOMES.index(outcome)] += 1
                    outcome = "clinician" if how == "confirmed" else outcome
                    counts_alone.setdefault(kind, [0, 0, 0])[OUTCOMES.index(outcome)] += 1
                    if name == "whisper":
                        said_again = (said, voice, noise, snr, AGAIN_SEEDS + seed)
                        ends = _over_the_dialogue(recogniser, item, truth, heard, said_again)
                        for table, end in zip(twice, ends, strict=True):
                            table.setdefault(kind, [0, 0, 0])[OUTCOMES.index(end)] += 1
            by_condition[condition] = _tally(counts)
            alone[condition] = _tally(counts_alone)
            if name == "whisper":
                dialogue[condition] = {
                    "without_repair": _tally(twice[0]),
                    "with_repair": _tally(twice[1]),
                }
        report = {
            "understood": by_condition,
            "real_time_factor": cpu / max(audio_s, 1e-9),
            "wall_s_per_answer": wall / max(answered, 1),
        }
        if (speech_dir / "fsdd").is_dir():
            report["real_speakers"] = real_speakers(speech_dir, recogniser)
        out["recognisers"][name] = report
        if name == "whisper":
            out["whisper_alone"] = alone
            out["whisper_dialogue"] = dialogue
    return out


def table(speech: dict[str, Any]) -> list[str]:
    if "recognisers" not in speech:  # the loop alone (--only speech_loop)
        return _loop_lines(speech.get("loop"))
    lines = [
        f"speech: {speech['answers_per_condition']} answers a condition, voices "
        f"{', '.join(speech['voices'])}; right / wrong / to the clinician"
    ]
    for name, report in speech["recognisers"].items():
        understood = report["understood"]
        kinds = sorted({k for c in understood.values() for k in c})
        lines.append(f"  {name}: " + "".join(f"{k:>24}" for k in kinds))
        for condition, counts in understood.items():
            cells = "".join(
                f"{c['right']:>9.0%} {c['wrong']:>5.1%} {c['clinician']:>6.0%}"
                for c in (counts[k] for k in kinds)
            )
            lines.append(f"    {condition:<14} {cells}")
        if "real_speakers" in report:
            r = report["real_speakers"]
            lines.append(
                f"    real speakers (FSDD one/two/three, {r['of']}): right {r['right']:.0%}, "
                f"wrong {r['wrong']:.1%}, to the clinician {r['clinician']:.0%}"
            )
        lines.append(
            f"    real-time factor {report['real_time_factor']:.3f}, "
            f"{report['wall_s_per_answer']:.2f} s of wall time an answer"
        )
    if "whisper_alone" in speech:
        lines.append("  whisper tiny.en alone, without the other opinions (the same run):")
        for condition, counts in speech["whisper_alone"].items():
            cells = "".join(
                f"{counts[k]['right']:>9.0%} {counts[k]['wrong']:>5.1%} "
                f"{counts[k]['clinician']:>6.0%}"
                for k in sorted(counts)
            )
            lines.append(f"    {condition:<14} {cells}")
    if "whisper_dialogue" in speech:
        lines.append(
            "  whisper over the dialogue (choose read back when not sure; words and serial "
            "asked again, taken when heard the same): right, wrong without -> with the repair"
        )
        for condition, both in speech["whisper_dialogue"].items():
            cells = "".join(
                f"  {k} "
                + " -> ".join(
                    f"{both[w][k]['right']:.0%} {both[w][k]['wrong']:.1%}"
                    for w in ("without_repair", "with_repair")
                )
                for k in sorted(both["with_repair"])
            )
            lines.append(f"    {condition:<14}{cells}")
    return lines + _loop_lines(speech.get("loop"))


def _loop_lines(loop: dict[str, Any] | None) -> list[str]:
    if not loop:
        return []
    if "error" in loop:
        return [f"  end of speech to the answer in the DSR: {loop['error']}"]
    d = loop["end_of_speech_to_dsr_ms"]
    lines = [
        f"  end of speech to the answer in the DSR ({loop['answers']} answers, --audio): "
        f"p50 {d['p50_ms']:.0f} ms, p99 {d['p99_ms']:.0f} ms"
    ]
    for name, run in loop.get("robot", {}).items():
        busiest = sorted(run["cpu_s"].items(), key=lambda kv: -kv[1])[:4]
        lines.append(
            f"  robot CPU, {name} --audio: {run['cpu_total_s']:.1f} s in {run['wall_s']:.0f} s "
            "(" + ", ".join(f"{n} {s:.1f}" for n, s in busiest) + ")"
        )
    return lines


LOOP_SCENARIOS = ("default.yaml", "mmse_normal.yaml")  # a Barthel, then a Mini-Mental


def bench_speech_loop(work: Path, domain: int, root: Path) -> dict[str, Any]:
    """End of speech to the answer in the DSR, through the whole loop with sound: the default
    Barthel scenario and the normal Mini-Mental, each run by scripts/launch.sh --audio (patient
    en-gb at 25 dB SNR of white noise, the robot at 300 words a minute, pace 0.7) and recorded
    to MCAP. For each hypothesis the asr node published (clarc/asr: its text and the capture
    time its speech ended) whose text Speech stored as an answer or as not understood, the time
    from that end to the recorder receiving the DSR delta that holds it: what any agent of the
    DSR sees. And the CPU seconds of every process of each run (launch.sh's CLARC_CPU_REPORT):
    the robot's cost of a test heard aloud."""
    delays: list[float] = []
    unmatched = 0
    per_scenario, robot = {}, {}
    for name in LOOP_SCENARIOS:
        run = _speech_loop_run(work, domain, root, name)
        if "error" in run:
            return {"error": f"{name}: {run['error']}"}
        delays += run["delays"]
        unmatched += run["unmatched"]
        per_scenario[name] = len(run["delays"])
        robot[name] = {
            "wall_s": run["wall_s"],
            "cpu_total_s": sum(run["cpu_s"].values()),
            "cpu_s": run["cpu_s"],
        }
    p50, p99 = np.percentile(delays, [50, 99])
    return {
        "answers": len(delays),
        "answers_per_scenario": per_scenario,
        "hypotheses_not_stored": unmatched,
        "end_of_speech_to_dsr_ms": {"p50_ms": 1000 * p50, "p99_ms": 1000 * p99},
        "robot": robot,
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
    cpu_report = work / f"aloud_{tag}_cpu.txt"
    cpu_report.unlink(missing_ok=True)
    env = dict(os.environ, ROS_DOMAIN_ID=str(domain), CLARC_CPU_REPORT=str(cpu_report))
    clock = time.perf_counter()
    run = subprocess.run(argv, capture_output=True, text=True, env=env, timeout=1000)
    wall = time.perf_counter() - clock
    if run.returncode != 0:
        return {"error": f"launch.sh exited {run.returncode}: {run.stderr[-2000:]}"}
    cpu = {}  # launch.sh's report: "node seconds" a line, user + system time of each process
    for line in cpu_report.read_text().splitlines() if cpu_report.exists() else []:
        name, seconds = line.split()
        cpu[name] = float(seconds)
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
    return {"delays": delays, "unmatched": unmatched + len(pending), "wall_s": wall, "cpu_s": cpu}
