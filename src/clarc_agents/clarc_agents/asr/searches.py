"""What the recogniser listens for while an item's answer is awaited (pure): restricted to what
the DSR says is expected, since a restricted search is both more accurate and twenty times
faster than free decoding here (../shared/docs/SPEECH.md).

- a ``choose`` item: a JSGF grammar of its options' phrases, an option by number or position
  ("option two", "the second one"), plus what is said to any item ("skip", "I don't know");
- a ``words`` item: the free English language model (any words: the date, a place, objects);
- a ``serial`` item: the free model too (a grammar of number sequences makes pocketsphinx's
  grammar search slower than real time);
- other items (touched, drawn, seen) are not answered by voice: no search.

Nothing here names a test or an item: only the item's kind, options and parts.
"""

from __future__ import annotations

import hashlib
import re
from collections.abc import Callable, Iterable
from dataclasses import dataclass

from clarc_agents.definitions import Item

FREE = "free"  # the search with the language model
ONES = "zero one two three four five six seven eight nine".split()
ORDINALS = ("first", "second", "third", "fourth", "fifth", "sixth")
# said to any item (questionnaire/answers.py understands them)
ANY_ITEM = ("skip", "next question", "i don't know", "i do not know", "not sure")
# said before an answer; none after it: a filler at the end soaks up the noise after the
# answer and the search ends inside it ("one it")
FILLERS = ("well", "i think", "it's", "it is")
# mumbling: heard as itself rather than forced into an option (then it is not understood);
# short words ("a", "oh", "the") would be heard in place of short answers ("three")
MUMBLING = ("um", "uh", "hmm", "mm", "eh", "er")


@dataclass(frozen=True)
class Search:
    """A search: ``name`` (stable for the same content, so a recogniser adds it once) and its
    JSGF grammar, or ``grammar`` None for the free language model."""

    name: str
    grammar: str | None


def _phrase_words(phrase: str) -> list[str]:
    return re.sub(r"[^a-z' ]+", " ", phrase.lower().replace("-", " ")).split()


def _alternatives(phrases: Iterable[str], known: Callable[[str], bool]) -> list[str]:
    """The phrases whose every word the recogniser's dictionary knows, as JSGF sequences."""
    out = []
    for phrase in phrases:
        tokens = _phrase_words(phrase)
        if tokens and all(known(t) for t in tokens):
            out.append(" ".join(tokens))
    return list(dict.fromkeys(out))


def _grammar(rules: dict[str, list[str]]) -> Search:
    lines = ["#JSGF V1.0;", "grammar answer;"]
    for name, alternatives in rules.items():
        public = "public " if name == "answer" else ""
        lines.append(f"{public}<{name}> = {' | '.join(alternatives)};")
    text = "\n".join(lines) + "\n"
    return Search("g" + hashlib.sha256(text.encode()).hexdigest()[:12], text)


def search_for(item: Item, known: Callable[[str], bool]) -> Search | None:
    """The search for ``item``'s answer; ``known(word)``: whether the dictionary has the word
    (a phrase with an unknown word cannot be recognised, so it is left out)."""
    anything = _alternatives(ANY_ITEM, known)
    fillers = _alternatives(FILLERS, known)
    if item.kind == "words":
        return Search(FREE, None)
    if item.kind == "serial":
        # the free model too: every grammar of number sequences tried (a loop of steps, nested
        # optional steps, sequences spelt out) made pocketsphinx's grammar search slower than
        # real time, up to minutes for a few seconds of speech, and no more accurate
        return Search(FREE, None)
    if item.kind != "choose":
        return None
    options = _alternatives((k for o in item.options for k in (o.text, *o.keywords)), known)
    count = ONES[1 : len(item.options) + 1]
    rules = {
        "option": options,
        "position": [
            f"(option | number) ({' | '.join(count)})",
            f"the ({' | '.join(ORDINALS[: len(item.options)])}) [one]",
            *count,
        ],
        "filler": fillers,
        "mumbling": _alternatives(MUMBLING, known),
        "answer": [
            "[<filler>] (<option> | <position>)",
            "<mumbling> [<mumbling>] [<mumbling>]",
            *anything,
        ],
    }
    return _grammar(rules)
