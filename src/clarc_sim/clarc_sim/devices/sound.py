"""Sound for the stand-ins (``--audio``): voices spoken by espeak-ng (Debian), room noise, and the
mix a microphone hears, all as 16 kHz mono int16 samples (clarc_agents/asr/audio.py's RATE).

Voices: ``Voice(name, words_per_minute, pitch)``, any espeak-ng voice ("en-us", "en-gb",
"en-gb-scotland", "en-us+f3", ...). Noise kinds: ``white`` (broadband hiss), ``babble`` (several
other voices talking at once, as a ward or a waiting room) and ``television`` (one voice over
music-like tones). ``noise_level(speech, snr_db)`` is the noise RMS that puts a voice at that
signal-to-noise ratio.
"""

from __future__ import annotations

import io
import math
import shutil
import subprocess
import wave
from dataclasses import dataclass
from functools import lru_cache

import numpy as np

from clarc_agents.asr.audio import RATE, resample
from clarc_sim.patient.scenario import NOISES

# what the voices of babble and the television say: ordinary talk, never a test's words
_TALK = (
    "did you see the match last night it went on and on",
    "the bus was late again this morning so I walked",
    "she said they would come over after lunch on the weekend",
    "and then the weather turned and we all went inside",
    "tonight on the news the council and the new road plans",
)


@dataclass(frozen=True)
class Voice:
    name: str = "en-us"
    words_per_minute: int = 150
    pitch: int = 50  # espeak-ng's 0 to 99

    def check(self) -> None:
        """ValueError naming what is wrong with the voice."""
        if not 80 <= self.words_per_minute <= 450:
            raise ValueError(f"rate {self.words_per_minute} words a minute: 80 to 450")
        if not 0 <= self.pitch <= 99:
            raise ValueError(f"pitch {self.pitch}: 0 to 99")


@lru_cache(maxsize=512)
def speak(text: str, voice: Voice = Voice()) -> np.ndarray:
    """``text`` said by ``voice``, 16 kHz int16 (espeak-ng writes 22.05 kHz; soxr resamples).
    RuntimeError when espeak-ng is missing or refuses the voice."""
    voice.check()
    exe = shutil.which("espeak-ng")
    if exe is None:
        raise RuntimeError("espeak-ng is not installed (apt-get install espeak-ng)")
    argv = [exe, "-v", voice.name, "-s", str(voice.words_per_minute), "-p", str(voice.pitch)]
    done = subprocess.run([*argv, "--stdout", text], capture_output=True, timeout=60)
    if done.returncode != 0 or not done.stdout.startswith(b"RIFF"):
        raise RuntimeError(f"espeak-ng {voice.name!r}: {done.stderr.decode(errors='replace')}")
    with wave.open(io.BytesIO(done.stdout)) as w:
        rate = w.getframerate()
        samples = np.frombuffer(w.readframes(w.getnframes()), dtype="<i2")
    out = resample(samples, rate)
    out.setflags(write=False)  # cached: shared by every caller
    return out


def rms(samples: np.ndarray) -> float:
    return float(np.sqrt(np.mean(np.square(samples.astype(np.float64))))) if len(samples) else 0.0


def speech_rms(samples: np.ndarray) -> float:
    """The level of a voice while it speaks: the RMS of its loudest half of 20 ms frames (the
    pauses between words would lower a plain RMS and so the noise an SNR allows)."""
    frame = RATE // 50
    n = len(samples) // frame
    if n == 0:
        return rms(samples)
    energies = np.sort(np.mean(np.square(samples[: n * frame].reshape(n, frame).astype(float)), 1))
    return float(math.sqrt(np.mean(energies[n // 2 :])))


def noise_level(speech_level: float, snr_db: float) -> float:
    """The noise RMS that puts speech of RMS ``speech_level`` at ``snr_db``."""
    return speech_level / 10 ** (snr_db / 20)


class RoomNoise:
    """An endless noise of one kind at a given RMS, read a chunk at a time."""

    def __init__(self, kind: str, level: float, seed: int = 0):
        if kind not in NOISES:
            raise ValueError(f"noise {kind!r}: one of {', '.join(NOISES)}")
        self.kind, self.level = kind, level
        self._rng = np.random.default_rng(seed)
        self._loop = None if kind == "white" else _loop(kind)
        self._at = 0

    def read(self, n: int) -> np.ndarray:
        """The next ``n`` samples (float64, RMS ``level``)."""
        if self._loop is None:
            return self._rng.normal(0.0, self.level, n)
        idx = (self._at + np.arange(n)) % len(self._loop)
        self._at = (self._at + n) % len(self._loop)
        return self._loop[idx] * self.level


@lru_cache(maxsize=2)
def _loop(kind: str) -> np.ndarray:
    """A loop of babble or television at RMS 1 (a few seconds, built once)."""
    if kind == "babble":
        voices = [Voice("en-us", 160, 40), Voice("en-gb", 150, 60), Voice("en-us+f3", 170, 55)]
        voices.append(Voice("en-gb-scotland", 140, 35))
        tracks = [
            np.concatenate([speak(t, v) for t in _TALK[k:] + _TALK[:k]]).astype(float)
            for k, v in enumerate(voices)
        ]
    else:  # television: one presenter over a slow chord
        voice = np.concatenate([speak(t, Voice("en-gb", 165, 45)) for t in _TALK]).astype(float)
        t = np.arange(len(voice)) / RATE
        chord = sum(np.sin(2 * np.pi * f * t) for f in (196.0, 246.9, 293.7))
        tracks = [voice, chord * 0.3 * rms(voice)]
    n = min(len(x) for x in tracks)
    mix = sum(x[:n] for x in tracks)
    return mix / rms(mix)


def mixed(parts: list[np.ndarray]) -> np.ndarray:
    """Float signals summed and clipped to int16."""
    n = max((len(p) for p in parts), default=0)
    total = np.zeros(n)
    for p in parts:
        total[: len(p)] += p
    return np.clip(np.round(total), -32768, 32767).astype(np.int16)


class Sources:
    """What the microphone hears, summed sample by sample (pure): sounds queued to start at a
    given stream sample, over the room's noise."""

    def __init__(self, noise: RoomNoise):
        self.noise = noise
        self._sounds: list[tuple[int, np.ndarray]] = []  # (first stream sample, float samples)

    def add(self, at: int, samples: np.ndarray) -> None:
        self._sounds.append((at, samples.astype(float)))

    def read(self, at: int, n: int) -> np.ndarray:
        """Stream samples ``at`` .. ``at + n`` as int16."""
        out = self.noise.read(n)
        kept = []
        for start, sound in self._sounds:
            lo, hi = max(at, start), min(at + n, start + len(sound))
            if lo < hi:
                out[lo - at : hi - at] += sound[lo - start : hi - start]
            if start + len(sound) > at + n:
                kept.append((start, sound))
        self._sounds = kept
        return np.clip(np.round(out), -32768, 32767).astype(np.int16)
