"""Where the voice is in an utterance, and how far it stands above the room (pure but for the
VAD): 30 ms frames that WebRTC's voice activity detector calls speech and that stand out of the
room.

The voice over the room (``Span.snr_db``) is the mean energy of the louder half of the voiced
frames over that of the quietest fifth of all frames (the room between words and around the
answer), as the speech benchmark sets its noise (``clarc_sim.devices.sound.speech_rms``). On the
benchmark's audio it reads a true 20 dB as 21 to 24, 10 dB as 7 to 13, 5 dB as 2 to 5 and
babble at 10 dB as 12 to 18 (BENCHMARKS.md section 9b, "A noisy room")."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from pocketsphinx import Vad

from clarc_agents.asr.audio import RATE

MIN_SPEECH = 0.12  # s of frames above the room's level: less is a click or a breath
MIN_RANGE = 6.0  # dB from the room to the loudest frame: less is a steady noise, not a voice
ROOM_SHARE = 0.2  # the quietest fifth of the frames is the room
# a words or serial answer heard with the voice less than this over the room is never sure:
# halfway between the readings of a true 10 dB (at most 13.3) and 20 dB (at least 21.1) on the
# benchmark's audio; below it Whisper scored 4 to 15% of such answers wrong (section 9b)
QUIET_ENOUGH_DB = 17.0
GUARDED_KINDS = frozenset({"words", "serial"})


@dataclass(frozen=True)
class Span:
    start: float  # s into the samples
    end: float
    voiced: float  # s of speech
    snr_db: float | None = None  # the voice over the room; None when no voice stands out


def speech_span(samples: np.ndarray) -> Span:
    """The voice above the room in ``samples`` (16 kHz int16): frames the VAD calls speech that
    are 10 dB over the quietest tenth and within 35 dB of the loudest, or within 15 dB of the
    loudest (a clip cut tight at the speech has little room in it). A sound as level as a hiss
    (less than ``MIN_RANGE`` dB from its quietest tenth to its loudest frame) is no speech."""
    vad = Vad(Vad.LOOSE, RATE)
    size = vad.frame_bytes // 2
    n = len(samples) // size
    everything = Span(0.0, len(samples) / RATE, 0.0)
    if n == 0:
        return everything
    frames = samples[: n * size].astype(np.int16).reshape(n, size)
    energy = np.mean(frames.astype(np.float64) ** 2, axis=1)
    level = 10 * np.log10(energy + 1.0)
    peak, floor = float(level.max()), float(np.quantile(level, 0.1))
    if peak - floor < MIN_RANGE:
        return everything
    threshold = min(max(floor + 10.0, peak - 35.0), peak - 15.0)
    voiced = [k for k in np.flatnonzero(level >= threshold) if vad.is_speech(frames[k].tobytes())]
    if not voiced:
        return everything
    seconds = size / RATE
    return Span(
        voiced[0] * seconds,
        (voiced[-1] + 1) * seconds,
        len(voiced) * seconds,
        _over_the_room(energy, energy[voiced]),
    )


def _over_the_room(energy: np.ndarray, voiced: np.ndarray) -> float:
    """dB of the louder half of the ``voiced`` frames' energy over the quietest fifth of all."""
    voice = np.sort(voiced)[len(voiced) // 2 :].mean()
    room = np.sort(energy)[: max(1, round(len(energy) * ROOM_SHARE))].mean()
    return 10 * math.log10(max(voice - room, 1.0) / max(room, 1.0))


def too_noisy(kind: str, snr_db: float | None) -> bool:
    """Whether an answer of ``kind`` heard with the voice ``snr_db`` over the room can never be
    sure: a list of words or numbers heard in noise (a choose answer keeps its read-back)."""
    return kind in GUARDED_KINDS and snr_db is not None and snr_db < QUIET_ENOUGH_DB
