"""What the recogniser listens for while an item's answer is awaited (pure): restricted to what
the DSR says is expected, since a restricted search is both more accurate and twenty times
faster than free decoding here (../shared/docs/SPEECH.md).

- a ``choose`` item: a JSGF grammar of its options' phrases, an option by number or position
  ("option two", "the second one"), plus what is said to any item ("skip", "I don't know").
  Not a denial before an option ("I can't ... by myself") nor "the last one": tried, each
  soaked up what patients said ("I walk on my own" heard "not walk on my own", "Yes, I
  control them" heard "the last one", both at confidence 0.6 to 1.0, in test_audio's run);
- a ``words`` item: a vocabulary (any sequence of its words, each as likely) of its parts'
  words, the other members of their word classes (a weekday brings the other weekdays, a number
  every number word), so that a wrong answer is heard as itself rather than as the right one,
  and a few short words that soak up what else is said ("and", "the", "um");
- a ``serial`` item: a vocabulary of the cardinal numbers, "minus", "take away", "is", "um";
- other items (touched, drawn, seen) are not answered by voice: no search; with no item, the
  free English language model (``clarc hear`` without an item).

Why vocabularies and not the free model or grammars (bench/speech.py, BENCHMARKS.md section 9):
the free model understood none of the synthesised serial and words answers, and a JSGF grammar
that loops over even fifty words made pocketsphinx's grammar search ten times slower than real
time; a vocabulary goes through the n-gram search (a uniform one-word model), at about a
twentieth of real time.

Nothing here names a test or an item: only the item's kind, options and parts.
"""

from __future__ import annotations

import hashlib
import re
from collections.abc import Callable, Iterable
from dataclasses import dataclass

from clarc_agents.definitions import Item
from clarc_agents.questionnaire.orientation import MONTHS, SEASON_WORDS, SEASONS, WEEKDAYS
from clarc_agents.questionnaire.spoken import ORDINAL_TENS, ORDINAL_UNITS, TENS, UNITS

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


# English word classes: a part's word brings its class, so that another member said is heard
# as itself (the patient's "Monday" is not forced into the expected "Tuesday")
CLASSES = (
    tuple(w.lower() for w in WEEKDAYS),
    tuple(m.lower() for m in MONTHS),
    tuple(dict.fromkeys(w for s in SEASONS.values() for w in SEASON_WORDS.get(s, (s,)))),
)
CARDINALS = (*UNITS, *TENS, "hundred")
NUMBER_WORDS = (*CARDINALS, *ORDINAL_UNITS, *ORDINAL_TENS, "thousand", "oh")
SUBTRACTING = ("minus", "take", "away", "is", "equals", "leaves", "makes")
# a serial answer's vocabulary is the cardinals and these words only: with the ordinals and
# every absorber ("do" of "I do not know", "the") a number's parts were heard as them ("ninety
# three" as "ninth the three"); measured on 72 answers: 9 understood right against 0 before
SERIAL_SOAKING = ("and", "um", "uh", "i", "think")
# short words that soak up what else is said; more of them lower the right words' share
# (measured: 6 of them hear 77% of the right words and force 13 wrong ones of 216 into them, 13
# hear 72% and force 3)
ABSORBERS = ("and", "a", "the", "of", "or", "um", "uh", "i", "it's", "oh", "well", "no", "so")


@dataclass(frozen=True)
class Search:
    """A search: ``name`` (stable for the same content, so a recogniser adds it once) and what it
    allows: a JSGF ``grammar``, or a ``vocabulary`` (any sequence of those words), or neither
    (the free language model)."""

    name: str
    grammar: str | None
    vocabulary: tuple[str, ...] = ()

    @property
    def kind(self) -> str:
        return "grammar" if self.grammar else "vocabulary" if self.vocabulary else "free"


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


def _vocabulary(words: Iterable[str], known: Callable[[str], bool]) -> Search:
    chosen = tuple(sorted({w for w in words if known(w)}))
    digest = hashlib.sha256(" ".join(chosen).encode()).hexdigest()[:12]
    return Search("v" + digest, None, chosen)


def _has_digit(text: str) -> bool:
    return any(c.isdigit() for c in text)


def _with_classes(tokens: Iterable[str]) -> set[str]:
    """``tokens`` and the members of their classes; digits bring the number words."""
    out: set[str] = set()
    for token in tokens:
        if _has_digit(token):
            out.update(NUMBER_WORDS)
            continue
        out.add(token)
        for members in CLASSES:
            if token in members:
                out.update(members)
    return out


def search_for(item: Item, known: Callable[[str], bool]) -> Search | None:
    """The search for ``item``'s answer; ``known(word)``: whether the dictionary has the word
    (a phrase with an unknown word cannot be recognised, so it is left out)."""
    anything = _alternatives(ANY_ITEM, known)
    fillers = _alternatives(FILLERS, known)
    said_to_any = [w for phrase in ANY_ITEM for w in _phrase_words(phrase)]
    if item.kind == "words":
        keywords = [k for part in item.parts for k in part.keywords]
        # a keyword with digits ("2026", "1st") stands for the number words it is said with
        parts = [w for k in keywords for w in ([k] if _has_digit(k) else _phrase_words(k))]
        return _vocabulary([*_with_classes(parts), *ABSORBERS, *said_to_any], known)
    if item.kind == "serial":
        return _vocabulary([*CARDINALS, *SUBTRACTING, *SERIAL_SOAKING], known)
    if item.kind != "choose":
        return None
    options = _alternatives((k for o in item.options for k in (o.text, *o.keywords)), known)
    mumbling = _alternatives(MUMBLING, known)
    count = ONES[1 : len(item.options) + 1]
    rules = {
        "position": [
            f"(option | number) ({' | '.join(count)})",
            f"the ({' | '.join(ORDINALS[: len(item.options)])}) [one]",
            *count,
        ],
    }
    # a rule with no alternative is no JSGF: one whose words the dictionary lacks is left out
    optional = [("option", options), ("filler", fillers), ("mumbling", mumbling)]
    rules |= {name: alternatives for name, alternatives in optional if alternatives}
    chosen = "<option> | <position>" if options else "<position>"
    rules["answer"] = [
        f"{'[<filler>] ' if fillers else ''}({chosen})",
        *(["<mumbling> [<mumbling>] [<mumbling>]"] if mumbling else []),
        *anything,
    ]
    return _grammar(rules)
