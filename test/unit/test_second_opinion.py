"""pocketsphinx's second opinion on what Whisper is not sure of (clarc_agents/asr/
second_opinion.py): only the same answer, heard as the same words, makes it sure; the
transcripts below are what each recogniser wrote in the speech benchmark's audio."""

from datetime import date

import pytest

from clarc_agents import definitions
from clarc_agents.asr.recogniser import Heard
from clarc_agents.asr.searches import search_for
from clarc_agents.asr.second_opinion import SecondOpinion, agree, confirmed, wanted
from clarc_agents.questionnaire.orientation import DEFAULT_PLACE, values

MMSE = definitions.load("mmse").filled(values(date(2026, 12, 1), DEFAULT_PLACE))
SERIAL, NAMING, RECALL = MMSE.item("attention"), MMSE.item("naming"), MMSE.item("recall")
FEEDING = definitions.load("barthel").item("feeding")
NAMING_WORDS = frozenset({"pencil", "watch", "or", "and", "the", "a", "of", "uh"})
RECALL_WORDS = frozenset({"apple", "table", "penny", "and", "a", "the"})
SERIAL_WORDS = frozenset(search_for(SERIAL, lambda word: True).vocabulary)


def test_the_same_numbers_in_order_are_the_same_serial_answer():
    assert agree(
        SERIAL, "93, eighty seven, eighty.", "ninety three eighty seven eighty", SERIAL_WORDS
    )
    # narrated: "minus seven" heard as "minus seventy" gives the same numbers
    assert agree(
        SERIAL,
        "100 minus seven is 93 minus seven in 86 minus seven in 80.",
        "one hundred minus seventy ninety three minus seven is eighty six minus seven leaves "
        "eighty",
        SERIAL_WORDS,
    )
    assert not agree(SERIAL, "93, 87.", "ninety three eighty six", SERIAL_WORDS)


def test_agreeing_that_nothing_was_right_is_no_agreement():
    place = MMSE.item("orientation_place")
    # "Seville", heard as two different nothings, both worth 0
    assert not agree(place, "Some wheels.", "two no", frozenset({"two", "no"}))


def test_a_words_answer_must_be_the_same_words_of_the_vocabulary_hedges_included():
    # both credit "pencil", but pocketsphinx heard the hedge ("or") Whisper missed
    assert not agree(NAMING, "A pen for the pencil.", "of and or of pencil", NAMING_WORDS)
    assert not agree(NAMING, "Pencil and watch.", "pencil watch", NAMING_WORDS)
    assert agree(RECALL, "Apple table, penny.", "apple table penny", RECALL_WORDS)
    # words outside the vocabulary, and soaked-up ones, do not count
    assert agree(NAMING, "That watch.", "the watch", NAMING_WORDS)


def test_a_word_the_second_recogniser_could_not_have_heard_is_vouched_for_by_nothing():
    # "watch" heard as "wow" by one, as nothing by the other: both credit the pencil alone
    assert not agree(NAMING, "pencil, wow.", "pencil", NAMING_WORDS)
    # "one hundred" heard as "One turn": both give 1 and 93
    heard = "One turn with minus seven at 93."
    assert not agree(SERIAL, heard, "one and minus seventy ninety three", SERIAL_WORDS)


def test_agreement_makes_it_as_sure_as_both_doubts_together():
    first = Heard("Apple table, penny.", 0.42, 0.1, 1.5)
    second = Heard("apple table penny", 0.8, 0.0, 1.6)
    both = confirmed(RECALL, first, second, RECALL_WORDS)
    assert both.confidence == pytest.approx(1 - 0.58 * 0.2)
    assert (both.text, both.start, both.end) == (first.text, 0.1, 1.5)  # Whisper's words
    assert both.confirmed_by == "apple table penny"
    other = Heard("apple and penny", 0.9, 0.0, 1.6)
    assert confirmed(RECALL, first, other, RECALL_WORDS) == first


def test_only_a_words_or_serial_answer_understood_but_unsure_is_worth_a_second_opinion():
    assert wanted(RECALL, Heard("Apple table, penny.", 0.42, 0, 1), 0.5)
    assert not wanted(RECALL, Heard("Apple table, penny.", 0.6, 0, 1), 0.5)  # sure already
    assert not wanted(RECALL, Heard("", 0.0, 0, 1), 0.5)  # nothing heard
    assert not wanted(FEEDING, Heard("Two.", 0.3, 0, 1), 0.5)  # a choose item: read back
    assert not wanted(None, Heard("Two.", 0.3, 0, 1), 0.5)
    assert not wanted(SERIAL, Heard("Skip.", 0.3, 0, 1), 0.5)  # no answer to confirm
    # heard in noise: two recognisers agreeing on noise prove nothing (span.QUIET_ENOUGH_DB)
    assert not wanted(RECALL, Heard("Apple table, penny.", 0.42, 0, 1, snr_db=11.0), 0.5)
    assert wanted(RECALL, Heard("Apple table, penny.", 0.42, 0, 1, snr_db=22.0), 0.5)


class _Fixed:
    def __init__(self, heard, vocabulary=()):
        self.heard, self.vocabulary, self.calls = heard, vocabulary, 0

    def hear_item(self, samples, item):
        self.calls += 1
        return self.heard, "vocabulary"

    def vocabulary_of(self, item):
        return self.vocabulary


def test_the_second_recogniser_hears_only_what_the_first_doubts():
    unsure = _Fixed(Heard("Apple table, penny.", 0.42, 0, 1))
    second = _Fixed(Heard("apple table penny", 0.8, 0, 1), tuple(RECALL_WORDS))
    heard, how = SecondOpinion(unsure, second, 0.5).hear_item(None, RECALL)
    assert how == "confirmed" and heard.confidence > 0.5 and second.calls == 1
    sure = _Fixed(Heard("Apple, table, penny.", 0.9, 0, 1))
    heard, how = SecondOpinion(sure, second, 0.5).hear_item(None, RECALL)
    assert how == "vocabulary" and heard.confidence == 0.9 and second.calls == 1
    disagreeing = _Fixed(Heard("apple", 0.9, 0, 1), tuple(RECALL_WORDS))
    heard, how = SecondOpinion(unsure, disagreeing, 0.5).hear_item(None, RECALL)
    assert how == "vocabulary" and heard.confidence == 0.42 and not heard.confirmed_by
