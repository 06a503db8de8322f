"""The pocketsphinx recogniser (its wheel's en-US model: no download at run time): an
utterance's samples and a search (``searches.py``) in, what was heard out, with a confidence
(the lowest posterior probability of its words, 0 to 1) and its times within the samples.
``hearing.py`` chooses between it and Whisper (``whisper.py``); both give a ``Heard``."""

from __future__ import annotations

import math
import tempfile
from collections import OrderedDict
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from pocketsphinx import Config, Decoder

from clarc_agents.asr.audio import RATE, dithered
from clarc_agents.asr.searches import (
    ABSORBERS,
    FREE,
    MUMBLING,
    SERIAL_SOAKING,
    Search,
    search_for,
)
from clarc_agents.definitions import Item

FRAMES_PER_SECOND = 100  # pocketsphinx's frame rate (10 ms frames)
# quiet before and after the utterance: a recording cut tight at the speech (or an endpointer
# that ends right at its last word) gives the decoder no silence to start and end in
PAD = int(0.3 * RATE)
VOCABULARIES_KEPT = 16  # decoders of recent vocabularies (one is about 0.1 s to make)


@dataclass(frozen=True)
class Heard:
    text: str  # "" when nothing was recognised
    confidence: float  # 0 to 1
    start: float  # seconds into the utterance's samples
    end: float
    transcript: str = ""  # what free decoding wrote, when ``text`` is a candidate rescored
    confirmed_by: str = ""  # what a second recogniser heard, when it agreed (second_opinion.py)
    snr_db: float | None = None  # the voice over the room, where the recogniser measured it


class Recogniser:
    name = "pocketsphinx"

    def __init__(self):
        # the language model is loaded once (about 0.3 s); grammars are added as needed
        self.decoder = Decoder(Config(loglevel="FATAL"))
        self.decoder.add_lm(FREE, self.decoder.get_lm())
        self._added = {FREE}
        # a vocabulary is searched by a decoder of its own: the dictionary is a decoder's
        self._vocabularies: OrderedDict[str, Decoder] = OrderedDict()
        self._files = tempfile.TemporaryDirectory(prefix="clarc-asr-")

    def known(self, word: str) -> bool:
        """Whether the dictionary has ``word`` (a grammar can use only such words)."""
        return self.decoder.lookup_word(word) is not None

    def _decoder_for(self, search: Search) -> Decoder:
        if search.vocabulary:
            return self._vocabulary_decoder(search)
        if search.name not in self._added:
            self.decoder.add_jsgf_string(search.name, search.grammar)
            self._added.add(search.name)
        self.decoder.activate_search(search.name)
        return self.decoder

    def _vocabulary_decoder(self, search: Search) -> Decoder:
        """A decoder whose dictionary is the vocabulary's words (with every pronunciation the
        full dictionary gives) and whose language model makes each as likely: a uniform
        unigram model in ARPA, the format's simplest case (no estimate to make)."""
        decoder = self._vocabularies.get(search.name)
        if decoder is not None:
            self._vocabularies.move_to_end(search.name)
            return decoder
        folder = Path(self._files.name)
        lines = []
        for word in search.vocabulary:
            variant, n = word, 1
            while (phones := self.decoder.lookup_word(variant)) is not None:
                lines.append(f"{variant} {phones}")
                n += 1
                variant = f"{word}({n})"
        (folder / f"{search.name}.dict").write_text("\n".join(lines) + "\n")
        log10 = f"{math.log10(1 / (len(search.vocabulary) + 1)):.4f}"
        arpa = ["\\data\\", f"ngram 1={len(search.vocabulary) + 2}", "", "\\1-grams:"]
        arpa += [f"{log10} </s>", "-99 <s>", *(f"{log10} {w}" for w in search.vocabulary)]
        (folder / f"{search.name}.arpa").write_text("\n".join([*arpa, "", "\\end\\", ""]))
        decoder = Decoder(
            Config(
                loglevel="FATAL",
                dict=str(folder / f"{search.name}.dict"),
                lm=str(folder / f"{search.name}.arpa"),
            )
        )
        self._vocabularies[search.name] = decoder
        if len(self._vocabularies) > VOCABULARIES_KEPT:
            self._vocabularies.popitem(last=False)
        return decoder

    def vocabulary_of(self, item: Item) -> tuple[str, ...]:
        """The words this recogniser can hear while ``item``'s answer is awaited (a grammar's
        or the free model's: none listed)."""
        search = search_for(item, self.known)
        return search.vocabulary if search is not None else ()

    def hear_item(self, samples: np.ndarray, item: Item | None) -> tuple[Heard, str]:
        """What ``samples`` say while ``item``'s answer is awaited (None: nothing is), and the
        kind of search that heard it."""
        search = (search_for(item, self.known) if item is not None else None) or Search(FREE, None)
        return self.hear(samples, search), search.kind

    def hear(self, samples: np.ndarray, search: Search) -> Heard:
        """What ``samples`` (16 kHz mono int16, one utterance) say, within ``search``."""
        decoder = self._decoder_for(search)
        decoder.start_utt()
        padded = np.concatenate([np.zeros(PAD, np.int16), samples, np.zeros(PAD, np.int16)])
        decoder.process_raw(dithered(padded).tobytes(), full_utt=True)
        decoder.end_utt()
        hypothesis = decoder.hyp()
        segments = decoder.seg() if hypothesis is not None else None
        words = [s for s in segments or () if not _filler(s.word)]
        if hypothesis is None or not hypothesis.hypstr.strip() or not words:
            return Heard("", 0.0, 0.0, len(samples) / RATE)
        # how sure: the least sure of the words that carry the answer (a soaked-up "um" or
        # "the" is often unsure and says nothing about the answer)
        meaningful = [s for s in words if _base(s.word) not in _SOAKING] or words
        confidence = min(1.0, min(s.prob for s in meaningful))
        pad = PAD / RATE
        return Heard(
            hypothesis.hypstr,
            float(confidence),
            max(0.0, words[0].start_frame / FRAMES_PER_SECOND - pad),
            min(len(samples) / RATE, (words[-1].end_frame + 1) / FRAMES_PER_SECOND - pad),
        )


_SOAKING = frozenset(ABSORBERS) | frozenset(MUMBLING) | frozenset(SERIAL_SOAKING)


def _base(word: str) -> str:
    """A dictionary entry's word: "the(2)" -> "the"."""
    return word.split("(", 1)[0]


def _filler(word: str) -> bool:
    return word.startswith(("<", "[", "+")) or word in ("<sil>",)
