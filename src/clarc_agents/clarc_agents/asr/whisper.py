"""Whisper (tiny.en for English, the multilingual base for other languages, through
faster-whisper and CTranslate2, int8 on the CPU): an utterance's samples and what the DSR
expects (``expectations.py``) in, what was heard out, with how sure.

How sure: beam search keeps its ``HYPOTHESES`` best transcripts with their log-probabilities;
each is understood as the item's answer would be (``Expectation.meaning``), and the confidence
is the probability mass of the hypotheses that mean what the best one means. "Two." and "Two"
agree; "Two." against "Three." is a coin toss and says so. For words and serial answers, the
least sure token of the best transcript bounds it too (``TOKEN_DOUBT``), counting with it the
other tokens the decoder saw there that lead to the same reading (``Expectation.reading``: the
same numbers, the same words but articles): "93" and "ninety-three" are one reading, so a
number Whisper could write two ways is not doubted for it, while "87" against "80" still is;
"A wristwatch" and "Wristwatch" are one, "pen or pencil" and "pen, pencil" are not.
The ``DOUBT_PLACES`` least sure tokens are looked into when they alone would leave the answer
unsure: the decoder's ``ALTERNATIVES`` likeliest other tokens there, each decoded on to the end
of the answer (an article always: which one was said, or none, is no reading's). The words
that narrate a serial answer's numbers ("minus seven is", the start said first) are doubted as
a words answer's words are, its numbers as numbers (``_scales``).
And a words or serial answer heard worth less than every point must beat the readings worth
more (all of it, or a missing part in place of one of the least sure words), forced through the
decoder too: one at least a fifth as likely leaves the robot unsure, so a misheard "ands" or
"watch" goes to the clinician rather than costing a point; a words answer must also beat, by
twenty to one (``HEDGE_ODDS``), the readings with a hedge ("or") in place of one of its words
where that changes its points ("A pen for the pencil." against "A pen or a pencil.").

A choose item whose best transcript means nothing ("So.", "City.") is rescored: each way of
choosing an option (its number, "option N", its text) and each way of choosing none ("I don't
know", "Skip"), and the free transcript itself, forced through the decoder (CTranslate2's
``align`` gives each token's probability); the options' share of that mass is the confidence.
The free transcript and the ways of choosing none stay in the race, so a patient who said
something else is not forced into an option; when one of them wins, the answer is the free
transcript, not understood (a "Skip" forced out of a mumble would close the item).

Never an answer (../shared/docs/SPEECH.md): an utterance with less than ``MIN_SPEECH`` of
voice above the room (``speech_span``); what Whisper writes on silence or noise ("Thank you.",
"You.") when the decoder itself says there was no speech (no-speech probability over
``NO_SPEECH`` and average log-probability under ``LOGPROB_FLOOR``, faster-whisper's own
thresholds), or any time for its known phrases of silence. Never sure: a transcript saying
one sentence three times in a row (``LOOP``), the decoder running away on noise; a words or
serial answer heard with the voice less than ``span.QUIET_ENOUGH_DB`` over the room.
"""

from __future__ import annotations

import math
import os
import re
from dataclasses import replace

import numpy as np

from clarc_agents import languages
from clarc_agents.asr.audio import RATE, dithered
from clarc_agents.asr.expectations import FREE, Expectation, expectation_for
from clarc_agents.asr.models import WHISPER_BASE, WHISPER_TINY_EN, ModelFiles, verified_folder
from clarc_agents.asr.recogniser import Heard
from clarc_agents.asr.span import MIN_SPEECH, Span, speech_span, too_noisy
from clarc_agents.definitions import Item
from clarc_agents.exceptions import ModelError
from clarc_agents.questionnaire.answers import find_phrase
from clarc_agents.questionnaire.spoken import unaccented, words

os.environ.setdefault("HF_HUB_OFFLINE", "1")  # a local folder only: never a download

BEAM = 5
HYPOTHESES = 5
MAX_TOKENS = 96  # an answer is a sentence or two; a runaway repetition stops here
WINDOW_FRAMES = 3000  # Whisper's 30 s window of 10 ms mel frames (shorter ones hear worse)
NO_SPEECH = 0.6
LOGPROB_FLOOR = -1.0
# words and serial answers: a token's probability (a serial answer's with the other tokens
# there of the same reading) times this bounds the confidence, so that at Speech's 0.5 a words
# answer needs each word at 0.4 and a serial one each number at 0.65 (BENCHMARKS.md section 9:
# at 0.3 for words 3.8 to 15% were scored wrong; with other spellings counted, at 0.6 two
# serial answers were, "eighty" heard "87" and "eighty six" "96", each number at 0.61 to 0.63)
TOKEN_DOUBT = {"words": 0.5 / 0.4, "serial": 0.5 / 0.65}
# the least sure tokens looked into, and the other tokens tried at each (those the decoder gives
# at least MIN_ALTERNATIVE): other spellings of the same reading count with the token heard
DOUBT_PLACES = 3
ALTERNATIVES = 5
MIN_ALTERNATIVE = 0.01
LOOKED_INTO_BELOW = 0.5  # a token bound under Speech's min_confidence: worth looking into
# a words answer only when the DSR expects every word of it (expectations.py's ``unexpected``):
# looked into otherwise, "Pen, hold up pencil." for "a pen or a pencil" was sure (0.76), its
# "pencil" written two ways (BENCHMARKS.md section 9c)
LOOKED_INTO = ("serial", "words")
# a words or serial answer heard worth less than every point: its confidence is at most this
# over the odds of the likeliest reading worth more (at Speech's 0.5: such a reading may be at
# most a fifth as likely as what was heard); checked only for answers sure enough otherwise
RIVAL_ODDS = 0.1
# a hedge in place of a word heard (``_hedged``): at Speech's 0.5 it may be at most a twentieth
# as likely ("A pen for a pencil." was sure at 0.56 with "A pen or a pencil." 0.14 as likely,
# "A pen for the pencil." at 0.55 with it 0.07 as likely)
HEDGE_ODDS = 0.025
CHECKED_ABOVE = 0.3
RIVAL_PLACES = 2  # a missing part is tried in place of each of the least sure words heard
LOOP = 3  # one sentence this many times in a row is the decoder running away, not an answer
WORD_LOOP = 4  # and one word this many times in a row ("Eme, me, me, me, me, me..." for a mumble)
# what Whisper writes where there is no speech (its training subtitles' closing lines), in the
# languages it hears for the robot, written as _said writes them
SILENCE_PHRASES = frozenset(
    {"thank you", "thanks", "thank you very much", "thanks for watching", "you", "bye", "okay"}
    | {"gracias", "muchas gracias", "adios", "hasta luego", "gracias por ver el video"}
    | {"subtitulos realizados por la comunidad de amara org", "suscribete"}
)
# the model that hears each language: tiny.en heard English best (BENCHMARKS.md section 9b)
MODEL_FOR = {"en": WHISPER_TINY_EN}


def _said(text: str) -> str:
    return re.sub(r"[^a-z' ]+", " ", unaccented(text.lower())).strip()


class WhisperRecogniser:
    name = "whisper"

    def __init__(self, language: str = "en", threads: int = 2, model: ModelFiles | None = None):
        from faster_whisper import WhisperModel
        from faster_whisper.tokenizer import Tokenizer

        folder = verified_folder(model or MODEL_FOR.get(language, WHISPER_BASE))
        self.language = language
        self.model = WhisperModel(
            str(folder), device="cpu", compute_type="int8", cpu_threads=threads
        )
        multilingual = self.model.model.is_multilingual
        if not multilingual and language != "en":
            raise ModelError(f"whisper: {folder.name} hears English only, not {language!r}")
        self.tokenizer = Tokenizer(self.model.hf_tokenizer, multilingual, "transcribe", language)

    # -- the decoder's inputs ---------------------------------------------------------------
    def _encode(self, samples: np.ndarray):
        audio = dithered(samples).astype(np.float32) / 32768.0
        features = self.model.feature_extractor(audio[: 30 * RATE])
        frames = min(features.shape[-1], WINDOW_FRAMES)
        padded = np.zeros((features.shape[0], WINDOW_FRAMES), dtype=features.dtype)
        padded[:, :frames] = features[:, :frames]
        return self.model.encode(padded), frames

    def _start(self, prompt: str) -> list[int]:
        tokenizer = self.tokenizer
        previous = [tokenizer.sot_prev, *tokenizer.encode(" " + prompt.strip())] if prompt else []
        # the previous text is kept short, as Whisper keeps it (half its context)
        previous = previous[:1] + previous[1:][-223:]
        return [*previous, *tokenizer.sot_sequence, tokenizer.no_timestamps]

    def _text(self, ids: list[int]) -> str:
        return self.tokenizer.decode([t for t in ids if t < self.tokenizer.eot]).strip()

    # -- hearing ----------------------------------------------------------------------------
    def hear_item(self, samples: np.ndarray, item: Item | None) -> tuple[Heard, str]:
        """What ``samples`` say while ``item``'s answer is awaited (None: nothing is), and how:
        ``prompted`` by the item's sentences, ``rescored`` over its options, or ``free``."""
        expectation = expectation_for(item) or FREE
        heard = self.hear(samples, expectation)
        how = "free" if expectation.kind == "free" else "prompted"
        return heard, "rescored" if heard.transcript else how

    def hear(self, samples: np.ndarray, expectation: Expectation) -> Heard:
        """What ``samples`` (16 kHz mono int16, one utterance) say, as ``expectation`` reads
        them, with the voice's level over the room."""
        span = speech_span(samples)
        return replace(self._heard(samples, expectation, span), snr_db=span.snr_db)

    def _heard(self, samples, expectation: Expectation, span: Span) -> Heard:
        start, end = span.start, span.end
        nothing = Heard("", 0.0, start, end)
        if span.voiced < MIN_SPEECH:
            return nothing
        encoded, frames = self._encode(samples)
        prompt = self._start(expectation.prompt)
        result = self.model.model.generate(
            encoded,
            [prompt],
            beam_size=BEAM,
            num_hypotheses=HYPOTHESES,
            max_length=len(prompt) + MAX_TOKENS,  # CTranslate2 counts the prompt in it
            return_scores=True,
            return_no_speech_prob=True,
        )[0]
        hypotheses = []  # (text, total log-probability)
        for ids, score in zip(result.sequences_ids, result.scores, strict=True):
            text = self._text(ids)
            hypotheses.append((text, score * max(len(ids), 1)))
        if not hypotheses or not hypotheses[0][0]:
            return nothing
        best, best_lp = hypotheses[0]
        tokens = max(len(result.sequences_ids[0]), 1)
        average = best_lp / (tokens + 1)  # faster-whisper's avg_logprob
        if result.no_speech_prob > NO_SPEECH and average < LOGPROB_FLOOR:
            return nothing
        if _said(best) in SILENCE_PHRASES:
            return nothing
        if _looping(best):  # someone spoke, but this is the decoder's, not theirs
            return Heard(best, 0.0, start, end)
        if too_noisy(expectation.kind, span.snr_db):
            # in noise Whisper is sure of its mistakes (section 9b: "A pen for the pencil." at
            # 10 dB): a list of words or numbers is asked again, then left to the clinician
            return Heard(best, 0.0, start, end)
        meaning = expectation.meaning
        if expectation.kind == "choose" and meaning(best) is None and expectation.candidates:
            if expectation.mumbled(best):  # forced into the options, a mumble became one
                return Heard(best, 0.0, start, end)
            return self._rescored(encoded, frames, prompt, expectation, best, start, end)
        confidence = _agreeing(hypotheses, meaning)
        if expectation.kind in TOKEN_DOUBT:
            # every hypothesis may agree on a word none is sure of ("Table unpainted." for
            # "table and penny"): the least sure token bounds the whole answer
            ids = result.sequences_ids[0]
            probs = self.model.model.align(encoded, prompt, [ids], frames)[0].text_token_probs
            said = self._words_of(ids, probs)
            doubt = self._doubt(encoded, prompt, ids, probs, expectation, best)
            confidence = min(confidence, doubt)
            if confidence >= CHECKED_ABOVE:
                said_in = languages.get(self.language)
                rivals = [
                    (RIVAL_ODDS, _better_readings(said, expectation)),
                    (HEDGE_ODDS, _hedged(said, expectation, said_in.hedges, said_in.articles)),
                ]
                confidence = min(confidence, self._beaten_by(encoded, frames, prompt, said, rivals))
        return Heard(best, confidence, start, end)

    def _spread(self, encoded, prompt: list[int], ids: list[int]) -> list[np.ndarray]:
        """The decoder's probabilities over its vocabulary at each token of ``ids``, forced."""
        forced = self.model.model.generate(
            encoded,
            [prompt + list(ids)],
            beam_size=1,
            max_length=len(prompt) + len(ids) + 1,
            return_logits_vocab=True,
        )[0]
        spread = []
        for logits in forced.logits[0][: len(ids)]:
            values = np.array(logits, dtype=np.float64)
            values = np.exp(values - values.max())
            spread.append(values / values.sum())
        return spread

    def _doubt(self, encoded, prompt, ids, probs, expectation: Expectation, best: str) -> float:
        """The bound the least sure token of ``best`` puts on the confidence: its probability
        (``probs``, forced), with those of the other tokens there that lead to the same reading
        (a words answer's only if the DSR expects each of its words, or at an article), times
        the token's ``TOKEN_DOUBT`` (``_scales``)."""
        scales = self._scales(ids, expectation)
        sure = [float(p) for p in probs]
        places = [k for k, t in enumerate(ids) if any(c.isalnum() for c in self._text([t]))]
        doubted = []
        if expectation.kind in LOOKED_INTO:
            expected = not expectation.unexpected(best)
            unsure = [
                k
                for k in places
                if scales[k] * sure[k] < LOOKED_INTO_BELOW and (expected or self._article(ids[k]))
            ]
            doubted = sorted(unsure, key=sure.__getitem__)[:DOUBT_PLACES]
        if doubted:
            spread = self._spread(encoded, prompt, ids)
            others = [
                (k, int(t))
                for k in doubted
                for t in np.argsort(spread[k])[::-1][:ALTERNATIVES]
                if t != ids[k] and t < self.tokenizer.eot and spread[k][t] >= MIN_ALTERNATIVE
            ]
            reading = expectation.reading(best), expectation.meaning(best)
            starts = [prompt + list(ids[:k]) + [t] for k, t in others]
            for (k, t), text in zip(others, self._decoded_on(encoded, starts), strict=True):
                if (expectation.reading(text), expectation.meaning(text)) == reading:
                    sure[k] += float(spread[k][t])
        return min((min(1.0, scales[k] * sure[k]) for k in places), default=0.0)

    def _article(self, token: int) -> bool:
        """Whether ``token`` is an article: which one was said, or none, is no reading's."""
        articles = languages.get(self.language).articles
        return self.tokenizer.decode([token]).strip().lower() in articles

    def _scales(self, ids: list[int], expectation: Expectation) -> list[float]:
        """Each token's ``TOKEN_DOUBT``: a serial answer's the kind's, but for the words that
        narrate its numbers (an operator, the step after it, the word after that: "minus seven
        is"; the start said first), a words answer's. Any other word keeps the kind's: "80, and
        minus seven" was "eighty seven, minus seven", its "and" the number's."""
        scale = TOKEN_DOUBT[expectation.kind]
        if expectation.kind != "serial" or len(expectation.numbers) < 2:
            return [scale] * len(ids)
        start = str(2 * expectation.numbers[0] - expectation.numbers[1])
        operators = set(languages.get(self.language).operators)
        said = words(self._text(ids), self.language)
        first = next((i for i, w in enumerate(said) if w.isdigit()), None)
        narrating = [
            w in operators
            or (i == first and w == start)
            or (i > 0 and said[i - 1] in operators and w.isdigit())  # the step
            or (i > 1 and said[i - 2] in operators and not w.isdigit())  # its "is"
            for i, w in enumerate(said)
        ]
        scales, word = [scale] * len(ids), []
        for k in range(len(ids)):
            word.append(k)
            if k + 1 < len(ids) and not self.tokenizer.decode([ids[k + 1]]).startswith(" "):
                continue
            # a word ends here; the said word it ends in ("One hundred" is one: "100")
            owner = len(words(self._text(ids[: k + 1]), self.language)) - 1
            if 0 <= owner < len(said) and narrating[owner]:
                for t in word:
                    scales[t] = TOKEN_DOUBT["words"]
            word = []
        return scales

    def _decoded_on(self, encoded, starts: list[list[int]]) -> list[str]:
        """What each of ``starts`` (a prompt and the first tokens of an answer) becomes,
        decoded to its end by beam search, in one batch."""
        if not starts:
            return []
        ended = self.model.model.generate(
            _batch(encoded, len(starts)),
            starts,
            beam_size=BEAM,
            max_length=max(map(len, starts)) + MAX_TOKENS,
        )
        return [self._text(result.sequences_ids[0]) for result in ended]

    def _words_of(self, ids: list[int], probs: list[float]) -> list[tuple[str, float]]:
        """The transcript's words (those with a letter or a digit), each with the probability of
        its least sure token."""
        out: list[list] = []
        for token, p in zip(ids, probs, strict=False):
            piece = self.tokenizer.decode([token])
            p = p if any(c.isalnum() for c in piece) else 1.0  # a comma is no doubt of a word
            if piece.startswith(" ") or not out:
                out.append([piece, p])
            else:
                out[-1][0] += piece
                out[-1][1] = min(out[-1][1], p)
        return [(w.strip(), p) for w, p in out if any(c.isalnum() for c in w)]

    def _beaten_by(self, encoded, frames, prompt, said, rivals: list[tuple[float, list[str]]]):
        """A bound on the confidence in the words ``said``: for each group of ``rivals`` (the
        odds it allows: readings worth more, ``_hedged``'s worth otherwise), how much less
        likely than ``said`` its likeliest is, over those odds; all forced in one batch."""
        texts = [t for _, group in rivals for t in group]
        if not texts:
            return 1.0
        heard, *scores = self._forced_all(
            encoded, frames, prompt, [" ".join(w for w, _ in said), *texts]
        )
        bound, start = 1.0, 0
        for allowed, group in rivals:
            if group:
                best_rival = max(scores[start : start + len(group)])
                odds = math.exp(min(best_rival - heard, 50.0))  # P(rival) / P(heard)
                bound = min(bound, allowed / odds)
            start += len(group)
        return bound

    def _rescored(self, encoded, frames, prompt, expectation, free, start, end) -> Heard:
        """The candidates and the free transcript forced through the decoder; the best of them
        with the share of the mass that means what it means."""
        texts = [*expectation.candidates, free]
        scored = list(zip(texts, self._forced_all(encoded, frames, prompt, texts), strict=True))
        scored.sort(key=lambda s: s[1], reverse=True)
        best = scored[0][0]
        meaning = expectation.meaning(best)
        if best == free or meaning is None or meaning[0] != "answer":
            # something else was said, or what chooses no option ("Skip" forced out of a mumble
            # would close the item): not understood, as it was heard
            return Heard(free, 0.0, start, end)
        return Heard(best, _agreeing(scored, expectation.meaning), start, end, transcript=free)

    def _forced_all(self, encoded, frames: int, prompt: list[int], texts: list[str]) -> list[float]:
        """log P(text | audio, prompt) of each of ``texts``, written as Whisper writes a short
        answer, forced through the decoder in one batch."""
        spelt = [
            " " + t[:1].upper() + t[1:] + ("" if t.endswith((".", "?", "!")) else ".")
            for t in texts
        ]
        ids = [self.tokenizer.encode(text) for text in spelt]
        aligned = self.model.model.align(
            _batch(encoded, len(ids)), prompt, ids, [frames] * len(ids)
        )
        return [float(sum(math.log(max(p, 1e-12)) for p in a.text_token_probs)) for a in aligned]


def _batch(encoded, size: int):
    """The encoded audio ``size`` times over, for one decoder call on several sequences."""
    if size == 1:
        return encoded
    batch = np.repeat(np.array(encoded), size, axis=0)
    return type(encoded).from_array(np.ascontiguousarray(batch))  # CTranslate2's StorageView


def _better_readings(said: list[tuple[str, float]], expectation: Expectation) -> list[str]:
    """Readings of the words ``said`` worth more than they are: every part said (the full
    answer), and each missing part in place of one of the ``RIVAL_PLACES`` least sure words,
    alone or with the word before or after it ("Some will." for "Seville": a part heard as
    two words); for a serial answer, each of its numbers put right (``_put_right``)."""
    full = expectation.full_marks
    text = " ".join(w for w, _ in said)
    heard = expectation.meaning(text)
    if not full or heard is None or heard[0] != "answer":
        return []
    worth = heard[1]
    unsure = sorted(range(len(said)), key=lambda k: said[k][1])[:RIVAL_PLACES]
    heard_words = words(text)
    missing = [part for part in full if not find_phrase(tuple(words(part)), heard_words)]
    readings = [", ".join(full)]
    for part in missing:
        for k in unsure:
            for start, end in ((k, k + 1), (k - 1, k + 1), (k, k + 2)):
                if start < 0 or end > len(said):
                    continue
                readings.append(
                    " ".join([*(w for w, _ in said[:start]), part, *(w for w, _ in said[end:])])
                )
    readings += _put_right(said, expectation)
    better = []
    for reading in dict.fromkeys(readings):
        meaning = expectation.meaning(reading)
        if meaning is not None and meaning[0] == "answer" and meaning[1] > worth:
            better.append(reading)
    return better


def _hedged(said: list[tuple[str, float]], expectation: Expectation, hedges, articles) -> list[str]:
    """A words answer's rivals with a hedge ("or") in place of one of its words, where that
    changes what it is worth, the article after it as said or as another: "A pen for a
    pencil." (the pencil credited) for "a pen or a pencil" (nothing: a hedge) was sure at 0.56
    once its first article was no longer doubted, and "A pen for the pencil." at 0.55 (tiny.en
    found "A pen or a pencil." 0.07 as likely, "A pen or the pencil." 0.0005): a reading worth
    less, which no other check tried."""
    if expectation.kind != "words":
        return []
    heard_words = [w for w, _ in said]
    heard = expectation.meaning(" ".join(heard_words))
    rivals = []
    for k, word in enumerate(heard_words):
        if word.strip(",.;:!?").lower() in hedges:
            continue
        after = heard_words[k + 1 : k + 2]
        swapped = [after]
        if after and after[0].lower() in articles:
            swapped += [[a] for a in articles if a != after[0].lower()]
        for hedge in hedges:
            for article in swapped:
                reading = " ".join([*heard_words[:k], hedge, *article, *heard_words[k + 2 :]])
                if expectation.meaning(reading) != heard:
                    rivals.append(reading)
    return list(dict.fromkeys(rivals))


def _put_right(said: list[tuple[str, float]], expectation: Expectation) -> list[str]:
    """A serial answer's rivals of its own length and form: each number written in digits
    replaced by one that would have scored after another (the item's first number, or one heard
    plus the step): "93, 87, 80, 73." for "93, 87, 87, 73.", which both Whisper models heard for
    "... eighty seven, eighty, seventy three" (there tiny.en found the rival over ten times less
    likely, so it did not move that answer: BENCHMARKS.md section 9e). The full answer alone is
    no rival for a patient's slip: it is far from what was said."""
    numbers = expectation.numbers
    if expectation.kind != "serial" or len(numbers) < 2:
        return []
    step = numbers[1] - numbers[0]
    heard = [int(n) for n in expectation.reading(" ".join(w for w, _ in said))]
    values = sorted({numbers[0], *(n + step for n in heard)})
    rivals = []
    for k, (word, _) in enumerate(said):
        if _DIGITS_ALONE.fullmatch(word) is None:
            continue
        for value in values:
            put = _DIGITS.sub(str(value), word, count=1)
            if put != word:
                rivals.append(
                    " ".join([*(w for w, _ in said[:k]), put, *(w for w, _ in said[k + 1 :])])
                )
    return rivals


_DIGITS = re.compile(r"\d+")
_DIGITS_ALONE = re.compile(r"\d+[,.;:!?]*")


def _looping(text: str) -> bool:
    """Whether ``text`` says one sentence ``LOOP`` times or more in a row, or one word
    ``WORD_LOOP`` times: Whisper's known runaway on noise ("Option three. Option three. Option
    three." in babble, scored as option three) and on a mumble ("Eme, me, me, me, me, me...",
    which rescoring then forced into an option, sure: the Spanish Barthel's dressing);
    faster-whisper guards the same with a compression ratio, which a short answer never
    reaches. A patient who repeats a word that often is left to the clinician, with the clip."""
    sentences = [_said(s) for s in re.split(r"[.!?]+", text) if _said(s)]
    return _runs(sentences, LOOP) or _runs(_said(text).split(), WORD_LOOP)


def _runs(units: list[str], length: int) -> bool:
    """Whether one of ``units`` comes ``length`` times or more in a row."""
    run = 1
    for before, after in zip(units, units[1:], strict=False):
        run = run + 1 if after == before else 1
        if run >= length:
            return True
    return False


def _agreeing(hypotheses: list[tuple[str, float]], meaning) -> float:
    """The probability mass of the hypotheses that mean what the first one means (log
    probabilities normalised over the list)."""
    top = max(lp for _, lp in hypotheses)
    weights = [math.exp(lp - top) for _, lp in hypotheses]
    first = meaning(hypotheses[0][0])
    same = sum(
        w for (text, _), w in zip(hypotheses, weights, strict=True) if meaning(text) == first
    )
    return same / sum(weights)
