"""Audio as the recogniser takes it (pure): 16 kHz mono PCM16 samples (numpy int16), read from
WAV files at any rate (resampled with soxr) or raw 16 kHz PCM16, and a little dither, since
digital silence (exact zeros, as synthetic audio has) breaks the recogniser's front end: a real
microphone never gives them (../shared/docs/SPEECH.md)."""

from __future__ import annotations

import wave
from pathlib import Path

import numpy as np
import soxr

from clarc_agents.exceptions import AudioError

RATE = 16000  # samples a second, as the acoustic model was trained
DITHER = 8.0  # standard deviation in PCM16 steps: -72 dB below full scale, far under any room


def resample(samples: np.ndarray, rate: int) -> np.ndarray:
    """``samples`` (mono, at ``rate``) at 16 kHz, int16."""
    if rate == RATE:
        return samples.astype(np.int16, copy=False)
    out = soxr.resample(samples.astype(np.float32), rate, RATE, quality="HQ")
    return np.clip(np.round(out), -32768, 32767).astype(np.int16)


def read_audio(path: str | Path) -> np.ndarray:
    """A WAV file (PCM 16 bit, mono or stereo, any rate) or a ``.raw`` file (PCM 16 bit little
    endian, mono, 16 kHz), as 16 kHz mono int16 samples."""
    path = Path(path)
    if path.suffix.lower() == ".raw":
        data = path.read_bytes()
        if len(data) % 2:
            raise AudioError(f"{path}: a .raw file is 16-bit samples: odd length {len(data)}")
        return np.frombuffer(data, dtype="<i2").astype(np.int16)
    try:
        with wave.open(str(path), "rb") as w:
            width, channels, rate = w.getsampwidth(), w.getnchannels(), w.getframerate()
            frames = w.readframes(w.getnframes())
    except (wave.Error, EOFError) as e:
        raise AudioError(f"{path}: not a PCM WAV file ({e})") from None
    if width != 2:
        raise AudioError(f"{path}: {8 * width}-bit samples; 16-bit PCM is read")
    samples = np.frombuffer(frames, dtype="<i2").reshape(-1, channels)
    mono = samples.mean(axis=1) if channels > 1 else samples[:, 0]
    if not len(mono):
        raise AudioError(f"{path}: no samples")
    return resample(mono, rate)


def dithered(samples: np.ndarray, seed: int = 0) -> np.ndarray:
    """``samples`` with a little noise added (reproducible: the same seed, the same noise)."""
    noise = np.random.default_rng(seed).normal(0.0, DITHER, len(samples))
    return np.clip(samples + noise, -32768, 32767).astype(np.int16)
