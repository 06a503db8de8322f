"""Confirming an answer heard without enough confidence, as a careful clinician does ("I heard:
I eat by myself. Is that right?"), answered yes or no by voice or on the touch screen (pure).

The confirmation is answered as any ``choose`` item: PELEA keeps its node in the DSR (``KEY``),
so Speech understands "yes" or "no" and Panel shows the two buttons without knowing about
confirmations. Only an option is ever confirmed (a choose item): a words or serial answer read
back would put words in the patient's mouth. One confirmation an item: after a "no" (or no
answer) the item is asked again as for words not understood, so a test does not drag.
"""

from __future__ import annotations

from functools import cache

from clarc_agents import languages
from clarc_agents.definitions import Item, Option
from clarc_agents.sentence import Sentence

KEY = "confirmation"  # the node of the yes/no answer (test_item_confirmation)
YES, NO = 1, 0
MOST = 1  # confirmations an item


@cache
def item_in(code: str) -> Item:
    """The yes/no item in language ``code`` (its words: the language's yes_words, no_words)."""
    said_in = languages.get(code)
    yes, no = said_in.say("yes"), said_in.say("no")
    return Item(
        KEY,
        said_in.say("is_it_right"),
        "",
        options=(
            Option(YES, yes, yes, said_in.yes_words),
            Option(NO, no, no, said_in.no_words),
        ),
        language=code,
    )


def sentence(item: Item, points: int) -> Sentence:
    """What the robot asks to confirm that ``item``'s answer is the option worth ``points``, in
    the item's language."""
    said_in, confirming = languages.get(item.language), item_in(item.language)
    option = item.option(points)
    answer = option.text if option is not None else said_in.say("points", points=points)
    return Sentence(
        f"{said_in.say('heard')} {answer}. {said_in.say('confirm')}",
        item=KEY,
        options=[o.text for o in confirming.options],
        option_points=[float(o.points) for o in confirming.options],
        input="options",
    )
