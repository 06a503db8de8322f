"""The clips of what the patient said (pure but for the files): each recognised utterance is
kept as a WAV file (16 kHz mono PCM16), the clinician's evidence for an answer the robot could
not understand. Written to a temporary name, flushed to disk and renamed, so a clip that a
result names is whole even if the asr node dies while writing the next."""

from __future__ import annotations

import os
import wave
from datetime import UTC, datetime
from pathlib import Path

import numpy as np

from clarc_agents.asr.audio import RATE


def default_folder() -> Path:
    """Where clips go when no folder is given: under ROS's home (``ROS_HOME``, else ~/.ros)."""
    home = os.environ.get("ROS_HOME") or os.path.join(os.path.expanduser("~"), ".ros")
    return Path(home) / "clarc" / "clips"


class Clips:
    def __init__(self, folder: str | Path):
        self.folder = Path(folder).resolve()
        self.folder.mkdir(parents=True, exist_ok=True)
        self._count = 0

    def keep(self, samples: np.ndarray, start: float) -> str:
        """``samples`` (captured from ``start``, epoch s) as a new clip: its absolute path."""
        self._count += 1
        when = datetime.fromtimestamp(start, UTC).strftime("%Y%m%dT%H%M%S.%f")[:-3]
        path = self.folder / f"{when}Z-{os.getpid()}-{self._count}.wav"
        partial = path.with_suffix(".part")
        with open(partial, "wb") as f:
            with wave.open(f, "wb") as w:
                w.setnchannels(1)
                w.setsampwidth(2)
                w.setframerate(RATE)
                w.writeframes(samples.astype("<i2").tobytes())
            f.flush()
            os.fsync(f.fileno())
        os.replace(partial, path)
        return str(path)
