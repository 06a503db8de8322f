"""A microphone's stream cut into utterances, each with its samples and when it started and
ended by the stream's own capture stamps (pure but for the VAD).

A frame (30 ms) is speech when WebRTC's voice activity detector (pocketsphinx's ``Vad``) says
so *and* it is ``GATE_DB`` louder than the room's noise floor (the quietest tenth of the last
few seconds' frames): other people talking in the room (babble, a television) are voices too,
and the VAD alone would hear one endless utterance. An utterance starts when ``RATIO`` of a
``WINDOW`` are speech (pocketsphinx's Endpointer's rule) and ends when as many of a longer
``END_WINDOW`` are not."""

from __future__ import annotations

import math
from collections import deque
from dataclasses import dataclass

import numpy as np
from pocketsphinx import Vad

from clarc_agents.asr.audio import RATE

WINDOW = 0.3  # s of audio in which RATIO must be speech for an utterance to start
RATIO = 0.9  # of the window that must agree to change state
# s in which RATIO must be quiet for it to end: longer than the pause at a comma ("I need some
# help, I do about half" is one answer)
END_WINDOW = 0.7
MAX_UTTERANCE = 20.0  # s: longer is cut there (someone reading aloud, not an answer)
GATE_DB = 10.0  # a speech frame is this much louder than the noise floor
PREROLL = 0.3  # s before the window that began an utterance, kept with it (a soft onset)
FLOOR_SECONDS = 4.0  # the floor is the quietest tenth of this much of the stream
FLOOR_SHARE = 0.1


@dataclass(frozen=True)
class Utterance:
    samples: np.ndarray  # 16 kHz int16
    start: float  # capture time of its first sample (epoch s)
    end: float


class Utterances:
    def __init__(
        self,
        window: float = WINDOW,
        ratio: float = RATIO,
        gate_db: float = GATE_DB,
        end_window: float = END_WINDOW,
    ):
        self._vad = Vad(Vad.LOOSE, RATE)
        self._frame = self._vad.frame_bytes
        seconds = self._frame / 2 / RATE
        self._window = max(2, round(window / seconds))
        self._needed = math.ceil(ratio * self._window)
        self._end_window = max(2, round(end_window / seconds))
        self._quiet_needed = math.ceil(ratio * self._end_window)
        self._tail: deque[bool] = deque(maxlen=self._end_window)
        self._gate = gate_db
        self._levels: deque[float] = deque(maxlen=round(FLOOR_SECONDS / seconds))
        self._recent: deque[tuple[bytes, bool]] = deque(maxlen=self._window)
        self._before: deque[bytes] = deque(maxlen=self._window + round(PREROLL / seconds))
        self._speech: list[bytes] | None = None  # the utterance under way
        self._start = 0.0
        self._pending = b""  # bytes not yet a whole frame
        self._processed = 0  # samples taken so far
        self._clock = (0, 0.0)  # (samples taken, capture stamp) at the newest chunk

    @property
    def under_way(self) -> float | None:
        """The capture time of the utterance under way (None: none is)."""
        return self._start if self._speech is not None else None

    def _stamp(self, sample: int) -> float:
        """The capture time of stream sample ``sample``."""
        at, stamp = self._clock
        return stamp + (sample - at) / RATE

    def _is_speech(self, frame: bytes) -> bool:
        samples = np.frombuffer(frame, dtype="<i2").astype(float)
        level = 10 * math.log10(float(np.mean(samples * samples)) + 1.0)
        self._levels.append(level)
        floor = float(np.quantile(self._levels, FLOOR_SHARE))
        return level >= floor + self._gate and self._vad.is_speech(frame)

    def feed(self, pcm: bytes, stamp: float) -> list[Utterance]:
        """A chunk of the stream (PCM16 LE, 16 kHz mono) whose first sample was captured at
        ``stamp``: the utterances it ended."""
        self._clock = (self._processed + len(self._pending) // 2, stamp)
        data = self._pending + pcm
        cut = len(data) - len(data) % self._frame
        self._pending = data[cut:]
        done = []
        for k in range(0, cut, self._frame):
            frame = data[k : k + self._frame]
            speech = self._is_speech(frame)
            self._recent.append((frame, speech))
            self._tail.append(speech)
            self._before.append(frame)
            self._processed += self._frame // 2
            voiced = sum(speech for _, speech in self._recent)
            if self._speech is None:
                if voiced >= self._needed:  # it began with the window (and a little before)
                    self._speech = list(self._before)
                    self._start = self._stamp(
                        self._processed - len(self._before) * self._frame // 2
                    )
                continue
            self._speech.append(frame)
            long = len(self._speech) * self._frame / 2 / RATE >= MAX_UTTERANCE
            quiet = len(self._tail) - sum(self._tail)
            if quiet >= self._quiet_needed or long:
                done.append(self._finish())
        return done

    def _finish(self) -> Utterance:
        samples = np.frombuffer(b"".join(self._speech), dtype="<i2").copy()
        self._speech = None
        self._recent.clear()
        self._before.clear()
        self._tail.clear()
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

    def speaking_at(self, stamp: float) -> bool:
        """Whether the robot was speaking at ``stamp``."""
        return any(a <= stamp <= b for a, b in self._spans)

    def spoke_over(self, start: float, end: float) -> bool:
        """Whether the robot spoke during most of ``start`` .. ``end`` (then what was heard is
        its own voice, or the patient talking over it: not an answer)."""
        length = max(end - start, 1e-6)
        overlap = sum(max(0.0, min(end, b) - max(start, a)) for a, b in self._spans)
        return overlap / length > 0.5
