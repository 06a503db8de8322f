"""A second recogniser's opinion on a words or serial answer Whisper is not sure of.

Whisper (a transformer trained on subtitles, decoding freely with the exchange as its context)
and pocketsphinx (an HMM of read American speech, searching only the item's vocabulary) hear
differently: their mistakes on the same audio are seldom the same. When Whisper understood a
words or serial answer but is not sure of it, pocketsphinx hears the same utterance; if it
understood the same answer, the two doubts are taken as independent and the confidence becomes
``1 - (1 - whisper's) * (1 - pocketsphinx's)`` (questionnaire/agreement.py): one less the
chance that both are wrong, were their mistakes independent; Speech still takes it only at its
``min_confidence``.

"The same answer" is strict (``agree``): the same points for the same parts (a serial answer's
numbers, in order; a words answer's credited words); something credited (two recognisers
agreeing that nothing was said right agree on nothing: "Seville" heard "Some wheels." and "two
no"); every word Whisper wrote one pocketsphinx could have heard (its vocabulary, a number, or
a function word: "pencil, wow." and pocketsphinx's "pencil" agree on the pencil, but nothing
vouches for the "wow" in place of the watch); and for a words answer the same words of the
vocabulary in the same order, "or", "and" and "no" included ("A pen for the pencil" and "of and
or of pencil" both credit "pencil", but the second heard a hedge). Each of those rules was
added for answers that were otherwise scored wrong on the speech benchmark's audio
(BENCHMARKS.md section 9b); with all of them, none was.

Choose answers are left to Whisper's own rescoring and the read-back (Speech's ``unsure``
outcome): on the same audio, pocketsphinx's grammar agreed with none of the choose answers
Whisper doubted (they mean no option, or Whisper's beams split between options).

pocketsphinx's dictionary also says what is no English word: a words answer in which Whisper
wrote one that the item never says either ("Appiancil." for "a pencil", sure at 0.75 and scored
0, BENCHMARKS.md section 9c) is sounds Whisper spelt, not what the patient said, so it is never
sure (``NOT_A_WORD``). In the section's 410 words answers no right one had such a word; seven
others had, each already unsure ("A mistwatch and a pencil.", "A car, a nog and a table.").

A larger model's opinion (``larger``: Whisper base, loaded when first needed) on a words answer
still not sure after pocketsphinx's: the same kind of model, so its mistakes are the smaller
one's far more often than independence says (both heard "93, 87, 87, 73." for "... eighty
seven, eighty, seventy three", 0.37 and 0.44 sure; "A pen for a pencil." for the hedge, 0.20
and 0.61). So it counts only as the repair counts a second utterance
(questionnaire/agreement.py): the same answer (``heard_alike``: a words answer's words but its
articles), each hearing at least ``BOTH_AT_LEAST`` sure on its own; and it is asked only then,
so that it costs nothing when it could not count (BENCHMARKS.md section 9e).

Another family's opinion (``other``: Moonshine base, moonshine.py, loaded when first needed) on
a serial answer still not sure after pocketsphinx's, in place of the larger model's (which now
hears words answers only: the two Whispers agreed on "94, 87, 87, 73." for "... eighty seven,
eighty, seventy three", section 9g): a model made apart from Whisper, whose mistakes on
the benchmark's serial answers were seldom Whisper's (of the 139 it was asked about that
Whisper had misheard, in five voices, it heard one the same way, together 0.36 sure, under
Speech's 0.5; section 9g). Its agreement (``heard_alike``: the same numbers in
order) counts as an independent hearing, each at least ``OTHER_AT_LEAST`` sure on its own.
Words answers are left out: it heard them the same as Whisper too seldom to pay (3 of 62
unsure ones on that audio) and once made one wrong ("a pen or a pencil").
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import replace

from clarc_agents.asr.expectations import expectation_for, numeric, said_by
from clarc_agents.asr.recogniser import Heard
from clarc_agents.asr.searches import ABSORBERS, MUMBLING, SERIAL_SOAKING
from clarc_agents.asr.span import too_noisy
from clarc_agents.definitions import Item
from clarc_agents.questionnaire.agreement import KINDS, independent, same_answer
from clarc_agents.questionnaire.answers import understand
from clarc_agents.questionnaire.spoken import words

# English function words: said around an answer's words, never one of them
FUNCTION_WORDS = frozenset(
    "a an the this that these those it its i me my you your we our he she they them his her"
    " their is am are was were be been do does did have has had in on at to of for with from"
    " by about as or and but if so no not yes then there here what which who well oh um uh".split()
)
MEANINGFUL = frozenset({"and", "or", "no"})  # a hedge, a list, a denial: never soaked up
# the most a words answer with a word no dictionary has is worth: under Speech's 0.5 and under
# the repair's FLOOR, so that two such hearings are not taken as one answer either
NOT_A_WORD = 0.3
IGNORED = (frozenset(ABSORBERS) | frozenset(MUMBLING) | frozenset(SERIAL_SOAKING)) - MEANINGFUL
# each of two Whisper models that agree must be at least this sure on its own (section 9e: at
# 0.35, "93, 87, 87, 73." heard by both at 0.37 and 0.44 was scored wrong)
BOTH_AT_LEAST = 0.4
# another family's opinion: the kinds it is asked about, and how sure each hearing must be on
# its own for their agreement to count (section 9g)
OTHER_KINDS = ("serial",)
OTHER_AT_LEAST = 0.1
# the larger model is asked about words answers only: on serial answers its agreement with
# tiny.en made one wrong ("94, 87, 87, 73." for "... eighty seven, eighty, seventy three", both
# at least 0.4 sure), and with Moonshine asked in its place 6 right ones of 460 were lost
LARGER_KINDS = ("words",)


def wanted(item: Item | None, heard: Heard, min_confidence: float) -> bool:
    """Whether ``heard`` is worth a second opinion: a words or serial answer understood but not
    sure, heard in a room quiet enough (``span.too_noisy``)."""
    if item is None or item.kind not in KINDS or not heard.text:
        return False
    if too_noisy(item.kind, heard.snr_db):  # two recognisers hearing noise prove nothing
        return False
    return heard.confidence < min_confidence and understand(item, heard.text).kind == "answer"


def strange_words(item: Item, text: str, known: Callable[[str], bool]) -> list[str]:
    """The words of ``text`` that are no word ``known`` has (numbers are), nor one the item
    says (its question, its request, its parts' phrases: "Universitario", "Rocio")."""
    own = said_by(item)
    return [w for w in words(text, item.language) if not _in_vocabulary(w, own) and not known(w)]


def _in_vocabulary(word: str, vocabulary: frozenset[str]) -> bool:
    """Whether the vocabulary has ``word``; a number always: it is said with the vocabulary's
    number words."""
    return word in vocabulary or numeric(word)


def agree(item: Item, first: str, second: str, vocabulary: frozenset[str]) -> bool:
    """Whether two transcripts give the same answer to ``item`` (see the module's docstring);
    ``vocabulary``: the words the second recogniser could hear."""
    if not same_answer(item, first, second):
        return False
    said = words(first)
    if not all(_in_vocabulary(w, vocabulary | FUNCTION_WORDS) for w in said):
        return False
    if item.kind == "words":
        compared = vocabulary - IGNORED
        heard = [w for w in words(second) if _in_vocabulary(w, compared)]
        return [w for w in said if _in_vocabulary(w, compared)] == heard
    return True


def confirmed(item: Item, first: Heard, second: Heard, vocabulary: frozenset[str]) -> Heard:
    """``first`` with the confidence of two recognisers that agree, or as it was."""
    if not second.text or not agree(item, first.text, second.text, vocabulary):
        return first
    both = independent(first.confidence, second.confidence)
    return replace(first, confidence=both, confirmed_by=second.text)


def heard_alike(item: Item, first: str, second: str) -> bool:
    """Whether two Whisper transcripts are the same answer (``same_answer``: for a serial one,
    its numbers in order, however narrated) and, for a words answer, the same words but its
    articles ("A pen or a pencil." and "Pen, pencil." are not one)."""
    if not same_answer(item, first, second):
        return False
    expectation = expectation_for(item)
    if item.kind != "words" or expectation is None:
        return True
    return expectation.reading(first) == expectation.reading(second)


class SecondOpinion:
    """Whisper, with pocketsphinx's opinion on the words and serial answers it is not sure of,
    then a larger model's (``larger``: made when first asked for) on words answers still not
    sure, and another family's (``other``, the same) on serial answers still not sure
    (``hear_item`` as each recogniser's; ``how`` is ``confirmed`` when another agreed)."""

    name = "whisper"

    def __init__(
        self,
        first,
        second,
        min_confidence: float,
        larger: Callable | None = None,
        other: Callable | None = None,
    ):
        self.first, self.second, self.min_confidence = first, second, min_confidence
        self._make_larger, self._larger = larger, None
        self._make_other, self._other = other, None

    def hear_item(self, samples, item: Item | None) -> tuple[Heard, str]:
        heard, how = self.first.hear_item(samples, item)
        if item is not None and item.kind == "words" and heard.confidence > NOT_A_WORD:
            if strange_words(item, heard.text, self.second.known):
                heard = replace(heard, confidence=NOT_A_WORD)
        if not wanted(item, heard, self.min_confidence):
            return heard, how
        other, _ = self.second.hear_item(samples, item)
        vocabulary = frozenset(self.second.vocabulary_of(item))
        both = confirmed(item, heard, other, vocabulary)
        if both.confidence < self.min_confidence and heard.confidence >= BOTH_AT_LEAST:
            if item.kind in LARGER_KINDS:
                both = self._asked_larger(samples, item, heard, both)
        if both.confidence < self.min_confidence and both.confidence >= OTHER_AT_LEAST:
            if item.kind in OTHER_KINDS:
                both = self._asked_other(samples, item, both)
        return both, "confirmed" if both.confirmed_by else how

    def _asked_larger(self, samples, item: Item, heard: Heard, so_far: Heard) -> Heard:
        """``so_far`` made surer by the larger model's hearing when it is ``heard_alike`` with
        ``heard`` and at least ``BOTH_AT_LEAST`` sure; as it was otherwise (or with none)."""
        if self._make_larger is None:
            return so_far
        if self._larger is None:
            self._larger = self._make_larger()
        larger, _ = self._larger.hear_item(samples, item)
        if larger.confidence < BOTH_AT_LEAST or not heard_alike(item, heard.text, larger.text):
            return so_far
        both = independent(so_far.confidence, larger.confidence)
        return replace(so_far, confidence=both, confirmed_by=so_far.confirmed_by or larger.text)

    def _asked_other(self, samples, item: Item, so_far: Heard) -> Heard:
        """``so_far`` made surer by another family's hearing of the same answer, at least
        ``OTHER_AT_LEAST`` sure; as it was otherwise (or with none)."""
        if self._make_other is None:
            return so_far
        if self._other is None:
            self._other = self._make_other()
        text, confidence = self._other.hear(samples)
        if confidence < OTHER_AT_LEAST or not heard_alike(item, so_far.text, text):
            return so_far
        both = independent(so_far.confidence, confidence)
        return replace(so_far, confidence=both, confirmed_by=so_far.confirmed_by or text)
