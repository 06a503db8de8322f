"""What the DSR expects to hear while an item's answer is awaited, as a recogniser's context
(pure). Nothing here names a test or an item: only the item's kind, its sentences and options.

- ``prompt``: what the robot said just before the answer (the item's question and request, a
  choose item's options read out), given to Whisper as the conversation's previous text, and
  for a words item the answer worth every point after it ("Spain, Andalusia, Seville, ...";
  "Apple, table, penny."): the words the DSR expects, spelt as the rules read them. On the
  speech benchmark's words answers (BENCHMARKS.md section 9c) that took the share heard right
  from 33% to 54% clean and from 35% to 52% at 20 dB, and the wrong ones from 2 to 0 and 2 to
  1 of 205: Whisper still writes what was said when it is another answer ("Apple, orange.",
  "France, Paris.", "A pen and a clock."), and the rivals below still check a lower score.
- ``candidates`` (choose items): what chooses each option (its number, "option N", its text),
  and what is no option ("I don't know", "skip"), for closed-set rescoring when the free
  decoding means nothing (../shared/docs/SPEECH.md: 20 of 20 digits where the free one heard
  "so", "see", "city"); never when it wrote only sounds of hesitation (``mumbled``): a mumble
  forced into the options was heard as one, sure (the Spanish Barthel's dressing, at 0.78).
- ``meaning(text)``: what a text would be worth as the answer (``understand``'s kind and
  points), so that a recogniser can tell how sure it is: hypotheses that mean the same answer
  add up, hypotheses that mean another one compete.
- ``reading(text)``: what two transcripts must share to be heard the same, however written:
  a serial answer's numbers ("93" and "ninety-three"), a words answer's words but its articles
  ("A wristwatch" and "Wristwatch"; "or", "and", "no" count). Another token the decoder saw
  that leads to the same reading is no doubt of the one heard (asr/whisper.py), but for a
  words answer only if every word of it is one the DSR expects (``unexpected``: the item's
  sentences and parts, the language's word lists, numbers): "Pen, hold up pencil." for "a pen
  or a pencil" is the decoder's "hold up" in place of a hedge, and its other spellings of
  "pencil" are no reason to believe it.
- ``full_marks`` (words and serial items): what is worth every point (each part's first
  word): the rivals a heard answer worth less must beat clearly
  (all of it, or one missing part in place of a word heard), or the robot is not sure of it
  ("No ifs, and, or buts" heard for "ands", "Pencil under wash" for "watch": scored 0 and 1
  point, sure, in the benchmark). It only takes certainty away, never gives an answer points
  it was not heard to be worth. A serial answer's ``numbers`` give it rivals of its own
  length too: one number heard put right (asr/whisper.py).
"""

from __future__ import annotations

from collections.abc import Callable, Hashable
from dataclasses import dataclass, field, replace

from clarc_agents import languages
from clarc_agents.definitions import Item, serial_numbers
from clarc_agents.questionnaire.answers import only_hesitations, understand
from clarc_agents.questionnaire.spoken import words


@dataclass(frozen=True)
class Expectation:
    kind: str  # choose | words | serial | free
    prompt: str = ""
    candidates: tuple[str, ...] = ()
    meaning: Callable[[str], Hashable | None] = field(default=lambda text: None, compare=False)
    full_marks: tuple[str, ...] = ()
    reading: Callable[[str], Hashable] = field(
        default=lambda text: tuple(words(text)), compare=False
    )
    # whether a text is only sounds of hesitation (a mumble: never rescored into an option)
    mumbled: Callable[[str], bool] = field(default=lambda text: False, compare=False)
    # a words item's: the words the DSR expects in its answer (the item's sentences and parts,
    # the language's word lists; numbers always): the others a text has (``unexpected``)
    expected_words: frozenset[str] = frozenset()
    # a serial item's numbers, in order (93, 86, ...): what a number heard should have been
    numbers: tuple[int, ...] = ()

    def unexpected(self, text: str) -> list[str]:
        """The words of ``text`` that the DSR does not expect (none when it expects any)."""
        if not self.expected_words:
            return []
        return [w for w in self.reading(text) if w not in self.expected_words and not numeric(w)]


# no item: hypotheses that are the same words agree
FREE = Expectation("free", meaning=lambda text: tuple(words(text)) or None)


def _meaning_for(item: Item) -> Callable[[str], Hashable | None]:
    def meaning(text: str) -> Hashable | None:
        understood = understand(item, text)
        if understood.kind == "not_understood":
            return None
        return (understood.kind, understood.points)

    return meaning


def expectation_for(item: Item | None) -> Expectation | None:
    """The context for ``item``'s answer; None for an item not answered by voice; ``FREE``
    with no item."""
    if item is None:
        return FREE
    if "voice" not in item.via:
        return None
    meaning = _meaning_for(item)
    if item.kind == "choose":
        # as questionnaire/sentences.py reads them out, the numbers as words, as they are heard
        said_in = languages.get(item.language)
        numbers = said_in.option_numbers
        read_out = [
            said_in.say("option", number=numbers[i], text=o.text)
            for i, o in enumerate(item.options)
        ]
        option = said_in.sentences["option"].split("{number}")[0].strip().lower()  # "option"
        candidates = [
            phrase
            for i, o in enumerate(item.options)
            for phrase in (numbers[i], f"{option} {numbers[i]}", o.text)
        ]
        said = [item.question, said_in.say("options_are"), *read_out, said_in.say("ask")]
        return Expectation(
            "choose",
            " ".join(said),
            tuple(dict.fromkeys([*candidates, *said_in.no_option])),
            meaning,
            mumbled=lambda text: only_hesitations(item, text),
        )
    full = tuple(part.keywords[0] for part in item.parts if part.keywords)
    if meaning(", ".join(full)) != ("answer", item.max):  # no one way to say it all
        full = ()
    prompt = f"{item.question} {item.ask}"
    if item.kind == "words" and full:
        said = ", ".join(part.spelt or part.keywords[0] for part in item.parts if part.keywords)
        prompt = f"{prompt} {said[0].upper()}{said[1:]}."
    expected = Expectation(item.kind, prompt, (), meaning, full)
    if item.kind == "serial":
        numbers = tuple(serial_numbers(item))
        return replace(expected, reading=_numbers_said(item.language), numbers=numbers)
    return replace(expected, reading=_words_said(item.language), expected_words=_expected(item))


def said_by(item: Item) -> frozenset[str]:
    """The words ``item`` itself says: its question, its request and its parts' phrases
    ("Universitario", "Rocio")."""
    parts = [k for part in item.parts for k in part.keywords]
    return frozenset(words(" ".join([item.question, item.ask, *parts]), item.language))


def _expected(item: Item) -> frozenset[str]:
    """The words the DSR expects in ``item``'s answer: those it says itself (``said_by``) and
    the words the understanding rules read in its language (seasons, weekdays, hedges, "I
    don't know"...)."""
    said_in = languages.get(item.language)
    lists = [w for name in languages.WORD_LISTS for w in getattr(said_in, name)]
    seasons = [w for ways in said_in.seasons for w in ways]
    return said_by(item) | frozenset(words(" ".join([*lists, *seasons]), item.language))


def numeric(word: str) -> bool:
    """A number ("26", "2nd"): said with the number words of any language, never a word a
    vocabulary lacks."""
    return any(c.isdigit() for c in word)


def _words_said(language: str) -> Callable[[str], tuple[str, ...]]:
    articles = frozenset(languages.get(language).articles)
    return lambda text: tuple(w for w in words(text, language) if w not in articles)


def _numbers_said(language: str) -> Callable[[str], tuple[str, ...]]:
    return lambda text: tuple(w for w in words(text, language) if w.isdigit())
