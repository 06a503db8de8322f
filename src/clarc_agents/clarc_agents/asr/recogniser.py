"""The recogniser (pocketsphinx, its wheel's en-US model: no download at run time): an
utterance's samples and a search (``searches.py``) in, what was heard out, with a confidence
(the lowest posterior probability of its words, 0 to 1) and its times within the samples."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from pocketsphinx import Config, Decoder

from clarc_agents.asr.audio import RATE, dithered
from clarc_agents.asr.searches import FREE, Search

FRAMES_PER_SECOND = 100  # pocketsphinx's frame rate (10 ms frames)
# quiet before and after the utterance: a recording cut tight at the speech (or an endpointer
# that ends right at its last word) gives the decoder no silence to start and end in
PAD = int(0.3 * RATE)


@dataclass(frozen=True)
class Heard:
    text: str  # "" when nothing was recognised
    confidence: float  # 0 to 1
    start: float  # seconds into the utterance's samples
    end: float


class Recogniser:
    def __init__(self):
        # the language model is loaded once (about 0.3 s); grammars are added as needed
        self.decoder = Decoder(Config(loglevel="FATAL"))
        self.decoder.add_lm(FREE, self.decoder.get_lm())
        self._added = {FREE}

    def known(self, word: str) -> bool:
        """Whether the dictionary has ``word`` (a grammar can use only such words)."""
        return self.decoder.lookup_word(word) is not None

    def hear(self, samples: np.ndarray, search: Search) -> Heard:
        """What ``samples`` (16 kHz mono int16, one utterance) say, within ``search``."""
        if search.name not in self._added:
            self.decoder.add_jsgf_string(search.name, search.grammar)
            self._added.add(search.name)
        self.decoder.activate_search(search.name)
        self.decoder.start_utt()
        padded = np.concatenate([np.zeros(PAD, np.int16), samples, np.zeros(PAD, np.int16)])
        self.decoder.process_raw(dithered(padded).tobytes(), full_utt=True)
        self.decoder.end_utt()
        hypothesis = self.decoder.hyp()
        segments = self.decoder.seg() if hypothesis is not None else None
        words = [s for s in segments or () if not _filler(s.word)]
        if hypothesis is None or not hypothesis.hypstr.strip() or not words:
            return Heard("", 0.0, 0.0, len(samples) / RATE)
        confidence = min(1.0, min(s.prob for s in words))
        pad = PAD / RATE
        return Heard(
            hypothesis.hypstr,
            float(confidence),
            max(0.0, words[0].start_frame / FRAMES_PER_SECOND - pad),
            min(len(samples) / RATE, (words[-1].end_frame + 1) / FRAMES_PER_SECOND - pad),
        )


def _filler(word: str) -> bool:
    return word.startswith(("<", "[", "+")) or word in ("<sil>",)
