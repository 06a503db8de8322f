"""Confirming an answer heard without enough confidence, as a careful clinician does ("I heard:
I eat by myself. Is that right?"), answered yes or no by voice or on the touch screen (pure).

The confirmation is answered as any ``choose`` item: PELEA keeps its node in the DSR (``KEY``),
so Speech understands "yes" or "no" and Panel shows the two buttons without knowing about
confirmations. Only an option is ever confirmed (a choose item): a words or serial answer read
back would put words in the patient's mouth. One confirmation an item: after a "no" (or no
answer) the item is asked again as for words not understood, so a test does not drag.
"""

from __future__ import annotations

from clarc_agents.definitions import Item, Option
from clarc_agents.sentence import Sentence

KEY = "confirmation"  # the node of the yes/no answer (test_item_confirmation)
HEARD = "I heard:"  # how a confirmation starts (the simulated patient knows it so)
YES, NO = 1, 0
ITEM = Item(
    KEY,
    "Is that right?",
    "",
    options=(
        Option(YES, "Yes", "Yes", ("yes", "yeah", "yep", "that's right", "correct", "it is")),
        Option(NO, "No", "No", ("no", "nope", "wrong", "not right", "that's not", "it isn't")),
    ),
)
MOST = 1  # confirmations an item


def sentence(item: Item, points: int) -> Sentence:
    """What the robot asks to confirm that ``item``'s answer is the option worth ``points``."""
    option = item.option(points)
    heard = option.text if option is not None else f"{points} points"
    return Sentence(
        f"{HEARD} {heard}. Is that right? Say yes or no, or touch it on the screen.",
        item=KEY,
        options=[o.text for o in ITEM.options],
        option_points=[float(o.points) for o in ITEM.options],
        input="options",
    )
