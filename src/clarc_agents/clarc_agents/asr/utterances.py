"""A microphone's stream cut into utterances (pocketsphinx's Endpointer: WebRTC voice activity
detection over a sliding window), each with its samples and when it started and ended by the
stream's own capture stamps (pure but for the VAD)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from pocketsphinx import Endpointer

from clarc_agents.asr.audio import RATE

WINDOW = 0.3  # s of audio the speech / no-speech decision is made over
RATIO = 0.9  # of the window that must agree to change state (pocketsphinx's default)
MAX_UTTERANCE = 20.0  # s: longer is cut there (a television left on, not an answer)


@dataclass(frozen=True)
class Utterance:
    samples: np.ndarray  # 16 kHz int16
    start: float  # capture time of its first sample (epoch s)
    end: float


class Utterances:
    def __init__(self, window: float = WINDOW, ratio: float = RATIO):
        self._endpointer = Endpointer(window=window, ratio=ratio)
        self._frame = self._endpointer.frame_bytes
        self._pending = b""  # bytes not yet a whole frame
        self._processed = 0  # samples given to the endpointer so far
        self._speech: list[bytes] = []
        self._start = 0.0
        self._clock = (0, 0.0)  # (samples processed, capture stamp) at the newest chunk

    def _stamp(self, seconds_in: float) -> float:
        """The capture time of the sample ``seconds_in`` seconds into the stream."""
        at, stamp = self._clock
        return stamp + seconds_in - at / RATE

    def feed(self, pcm: bytes, stamp: float) -> list[Utterance]:
        """A chunk of the stream (PCM16 LE, 16 kHz mono) whose first sample was captured at
        ``stamp``: the utterances it ended."""
        self._clock = (self._processed + len(self._pending) // 2, stamp)
        data = self._pending + pcm
        cut = len(data) - len(data) % self._frame
        self._pending = data[cut:]
        done = []
        for k in range(0, cut, self._frame):
            speech = self._endpointer.process(data[k : k + self._frame])
            self._processed += self._frame // 2
            if speech is not None:
                if not self._speech:
                    self._start = self._stamp(self._endpointer.speech_start)
                self._speech.append(speech)
            too_long = len(self._speech) * self._frame / 2 / RATE >= MAX_UTTERANCE
            if self._speech and (not self._endpointer.in_speech or too_long):
                done.append(self._finish())
        return done

    def _finish(self) -> Utterance:
        samples = np.frombuffer(b"".join(self._speech), dtype="<i2").copy()
        self._speech = []
        return Utterance(samples, self._start, self._start + len(samples) / RATE)


class RobotSpeech:
    """When the robot was speaking (its speaker's start and end events, by their stamps), so
    that its own voice in the microphone is never taken for the patient's answer."""

    KEEP = 20  # sentences remembered

    def __init__(self):
        self._spans: list[list[float]] = []  # [start, end]; end inf while it speaks

    def event(self, kind: str, stamp: float) -> None:
        if kind == "start":
            self._spans = [*self._spans[-self.KEEP :], [stamp, float("inf")]]
        elif kind in ("end", "stopped") and self._spans and self._spans[-1][1] == float("inf"):
            self._spans[-1][1] = stamp

    def spoke_over(self, start: float, end: float) -> bool:
        """Whether the robot spoke during most of ``start`` .. ``end`` (then what was heard is
        its own voice, or the patient talking over it: not an answer)."""
        length = max(end - start, 1e-6)
        overlap = sum(max(0.0, min(end, b) - max(start, a)) for a, b in self._spans)
        return overlap / length > 0.5
