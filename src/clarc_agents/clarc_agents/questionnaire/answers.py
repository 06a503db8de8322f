"""Understanding an answer to an item (pure). The rules, with their sources, are in
docs/FORMAT.md ("How answers are understood"); what was said is first made words and digits
(``spoken.words``: case, punctuation and how a number was said never matter).

Said, to a ``choose`` item: an utterance chooses an option by number or position ("two",
"option two", "number 2", "the second one", "the last one"), or by the option's keywords
(phrases, not where a word before denies them: "I can't eat by myself" is no "by myself"; the
option with the most hits wins, a tie is not understood). "I don't know" and its like are
never an option. Said, to a ``words`` item: a point for each part said, unless it was hedged
("Monday or Tuesday": no point for the weekday) or said among rival values of its kind (every
weekday recited); any words but hesitations are an answer ("I don't know" is one, worth 0). A
value taken back ("Tuesday, no, Thursday") is replaced by the one after it, to any item. Said,
to a ``serial`` item (the serial sevens): the numbers given as answers (not the "seven" of
"minus seven", nor the 93 of "93 minus 7 is 86" after 93 was given), a point for each that is
the one said before it, or the start, minus the step (93, 85, 78: 2 points). Touched, on a
``touches`` item: a point for each stage done in order. "skip" / "next question" asks to skip
the item. Anything else is not understood.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from functools import cache

from clarc_agents import languages
from clarc_agents.definitions import Item, serial_numbers
from clarc_agents.languages import Language
from clarc_agents.questionnaire.spoken import suffixed, words

# The words each rule reads are the item's language's (clarc_agents/languages/<code>.yaml):
# SKIP, HESITATIONS, UNKNOWING ("I don't know" is never an option, worth 0 to a words item),
# POSITION_WORDS, NEGATORS (they deny what follows them in the clause, within NEGATION_REACH
# words and no clause's end between: a recogniser writes no commas), CLAUSE_ENDS, ARTICLES,
# OPERATORS (the operand of a subtraction said aloud is no answer), CORRECTIONS ("Tuesday, no,
# Thursday"), and the kinds of value (weekdays, months, seasons) among which another said
# beside the right one is a rival.
NEGATION_REACH = 4
_DAYS = frozenset(suffixed(d) for d in range(1, 32))


@dataclass(frozen=True)
class Rules:
    """One language's words, as the rules read them."""

    lang: Language
    skip: tuple[tuple[str, ...], ...]
    hesitations: frozenset[str]
    unknowing: tuple[tuple[str, ...], ...]
    negators: frozenset[str]
    clause_ends: frozenset[str]
    corrections: tuple[tuple[str, ...], ...]
    kinds: tuple[frozenset[str], ...]

    def said(self, text: str) -> list[str]:
        return words(text, self.lang.code)

    def negating(self, token: str) -> bool:
        return token in self.negators or any(token.endswith(e) for e in self.lang.negating_endings)


@cache
def rules_of(code: str) -> Rules:
    lang = languages.get(code)

    def said(name: str) -> tuple[tuple[str, ...], ...]:
        return tuple(tuple(words(p, code)) for p in getattr(lang, name))

    return Rules(
        lang,
        said("skip"),
        lang.words("hesitations"),
        said("unknowing"),
        lang.words("negators"),
        lang.words("clause_ends"),
        said("corrections"),
        (
            frozenset(w.lower() for w in lang.weekdays),
            frozenset(w.lower() for w in lang.months),
            frozenset(w for ways in lang.seasons for w in ways),
        ),
    )


def _hesitating(rules: Rules, said: list[str]) -> bool:
    """Only sounds of hesitation, or letters alone: a recogniser spells a mumble out ("M-M-H,
    B-R-R"), and no answer to any item is a string of single letters."""
    return all(t in rules.hesitations or (len(t) == 1 and t.isalpha()) for t in said)


def only_hesitations(item: Item, text: str) -> bool:
    """Whether ``text`` is only sounds of hesitation in ``item``'s language (a mumble)."""
    r = rules_of(item.language)
    said = r.said(text)
    return bool(said) and _hesitating(r, said)


@dataclass(frozen=True)
class Understanding:
    kind: str  # "answer", "skip" or "not_understood"
    points: int | None = None
    matched: tuple[str, ...] = ()  # the parts (or the option) the answer was credited for
    why: tuple[str, ...] = field(default=())  # what was not credited, and why


def find_phrase(phrase: tuple[str, ...], said: list[str]) -> list[int]:
    """Where ``phrase`` starts in ``said`` (token positions)."""
    n = len(phrase)
    return [i for i in range(len(said) - n + 1) if n and tuple(said[i : i + n]) == phrase]


def _strip(said: list[str], phrases) -> list[str]:
    """``said`` without any of ``phrases``."""
    out = list(said)
    for phrase in phrases:
        for i in reversed(find_phrase(phrase, out)):
            del out[i : i + len(phrase)]
    return out


def understand(item: Item, text: str) -> Understanding:
    """What ``text``, said to ``item``, means (in the item's language)."""
    r = rules_of(item.language)
    taken_back: list[str] = []
    said = self_corrected(r.said(text), taken_back, _replaces(item), r)
    if not said:
        return Understanding("not_understood", why=("nothing was said",))
    if any(find_phrase(s, said) for s in r.skip):
        return Understanding("skip")
    if item.kind in ("words", "serial"):
        if _hesitating(r, said):
            return Understanding("not_understood", why=("only hesitations",))
        meaning = _serial(r, item, said) if item.kind == "serial" else _words(r, item, said)
    else:
        meaning = _choose(r, item, said)
    if not taken_back:
        return meaning
    why = tuple(f"{value}: taken back" for value in taken_back)
    return Understanding(meaning.kind, meaning.points, meaning.matched, meaning.why + why)


def _choose(r: Rules, item: Item, said: list[str]) -> Understanding:
    said = _strip(said, r.unknowing)  # "I don't know" is never an option ("don't" might be)
    if not said or _hesitating(r, said):
        return Understanding("not_understood", why=("no option was said",))
    n = _position(r, said, len(item.options))
    if n is not None:
        if 1 <= n <= len(item.options):
            option = item.options[n - 1]
            return Understanding("answer", option.points, (f"option {n}: {option.text}",))
        return Understanding("not_understood", why=(f"there is no option {n}",))
    hits = [(h, o) for h, o in zip(_keyword_hits(r, item, said), item.options, strict=True)]
    best = max(h for h, _ in hits)
    winners = [o for h, o in hits if h == best]
    if best == 0:
        return Understanding("not_understood", why=("no option's words were said",))
    if len(winners) > 1:
        tied = ", ".join(repr(o.text) for o in winners)
        return Understanding("not_understood", why=(f"as many words of {tied}",))
    return Understanding("answer", winners[0].points, (winners[0].text,))


def _keyword_hits(r: Rules, item: Item, said: list[str]) -> list[int]:
    """For each option, how many of its keywords were said, the longest taken first and each
    word counted for one keyword only: "no problems" is that keyword, not also the "no" of "I do
    not control them". A keyword denied where it is said ("I can't eat by myself": not "by
    myself") is no hit; one that is itself a denial ("can't", "no accidents") is one."""
    found = [
        (len(phrase), i, n, k)
        for n, option in enumerate(item.options)
        for k, phrase in enumerate(tuple(r.said(kw)) for kw in option.keywords)
        for i in find_phrase(phrase, said)
        if r.negating(phrase[0]) or not _denied(r, said, i)
    ]
    used: set[int] = set()
    hit: set[tuple[int, int]] = set()
    for length, i, n, k in sorted(found, key=lambda f: -f[0]):
        span = set(range(i, i + length))
        if not span & used:
            used |= span
            hit.add((n, k))
    return [sum(n == m for m, _ in hit) for n in range(len(item.options))]


def _denied(r: Rules, said: list[str], i: int) -> bool:
    """Whether what is said from ``said[i]`` on is denied by a word before it in its clause:
    "not", "never", "can't", ... up to NEGATION_REACH words before ("I don't drive but I take
    the bus": the bus is not denied)."""
    for t in reversed(said[max(0, i - NEGATION_REACH) : i]):
        if t in r.clause_ends:
            return False
        if r.negating(t):
            return True
    return False


def _position(r: Rules, said: list[str], options: int) -> int | None:
    """The option chosen by number or position: "2", "option 2", "number 2", "the 2nd (one)",
    "the last one" (the words already made digits)."""
    lang = r.lang
    if len(said) == 1 and said[0].isdigit():
        return int(said[0])
    last = said[1:] if said[:1] and said[0] in lang.definite_articles else said
    named = last[1:]  # "the last", "the last one", "the last option"
    if last[:1] and last[0] in lang.last and len(named) <= 1:
        if not named or named[0] in lang.ordinal_followers:
            return options
    for i, token in enumerate(said):
        if _denied(r, said, i):  # "not the second one", "not option two": no choice made
            continue
        if token in lang.position_words and i + 1 < len(said) and said[i + 1].isdigit():
            return int(said[i + 1])
        if token[:1].isdigit() and not token.isdigit():  # an ordinal: "the 2nd", "2nd 1"
            after = said[i + 1 : i + 2]
            if (i > 0 and said[i - 1] in lang.definite_articles) or (
                after and after[0] in lang.ordinal_followers
            ):
                return int(token.rstrip("stndrh"))
    return None


def _words(r: Rules, item: Item, said: list[str]) -> Understanding:
    points, matched, why = 0, [], []
    for part in item.parts:
        phrases = [tuple(r.said(k)) for k in part.keywords]
        spans = [(i, len(p)) for p in phrases for i in find_phrase(p, said)]
        if not spans:
            continue
        name = " ".join(phrases[0])
        if all(_hedged(r, said, i, n) for i, n in spans):
            why.append(f"{name}: hedged (said with 'or')")
            continue
        rivals = _rivals(r, {t for p in phrases for t in p}, said)
        if rivals:
            why.append(f"{name}: said among others of its kind ({', '.join(rivals)})")
            continue
        points += 1
        matched.append(name)
    return Understanding("answer", points, tuple(matched), tuple(why))


def _kind(r: Rules, token: str) -> object | None:
    """The kind of value ``token`` is (a weekday, a month, a season, a year, a day of the month,
    a number), or None."""
    for kind in r.kinds:
        if token in kind:
            return kind
    if _is_year(token):
        return "year"
    if token in _DAYS:
        return "day"
    return "number" if token.isdigit() else None


def _replaces(item: Item) -> Callable[[int, int], bool]:
    """Whether a number said after a correction replaces the one before it: in the serial
    sevens only when it is nearer to it than a step ("78, no, 79"), since "72, no, 65" is the
    next answer after a "no" of hesitation; elsewhere always ("2, no, 3" chooses option 3)."""
    if item.kind != "serial":
        return lambda before, after: True
    expected = serial_numbers(item)
    step = abs(expected[1] - expected[0])
    return lambda before, after: abs(before - after) < step


def self_corrected(
    said: list[str],
    taken_back: list[str],
    replaces: Callable[[int, int], bool],
    r: Rules,
) -> list[str]:
    """``said`` with each value the speaker took back left out, and the words that took it back:
    a value, a correction ("no", "sorry", "I mean", ...) and another value of its kind ("Tuesday,
    no, Thursday": Thursday; "78, I mean 79": 79; two numbers only if ``replaces`` them), each
    appended to ``taken_back``. Articles may stand on either side."""
    articles = r.lang.articles
    out = list(said)
    i = 0
    while i < len(out):
        marker = max(
            (c for c in r.corrections if out[i : i + len(c)] == list(c)), key=len, default=()
        )
        if not marker:
            i += 1
            continue
        before = i - 1 - (i >= 2 and out[i - 1] in articles)
        after = i + len(marker)
        after += after < len(out) and out[after] in articles
        kind = _kind(r, out[before]) if before >= 0 else None
        if (
            kind is None
            or after >= len(out)
            or _kind(r, out[after]) != kind
            or (kind == "number" and not replaces(int(out[before]), int(out[after])))
        ):
            i += 1
            continue
        taken_back.append(out[before])
        del out[before:after]
        i = before
    return out


def _hedged(r: Rules, said: list[str], i: int, n: int) -> bool:
    """The phrase at ``said[i:i+n]`` is one side of an "or": "Monday or Tuesday", "a pen or a
    pencil"."""
    hedges, articles = r.lang.hedges, r.lang.articles
    before = said[max(0, i - 2) : i]
    if before[-1:] and before[-1] in hedges:
        return True
    if before[-1:] and before[-1] in articles and before[:1] and before[0] in hedges:
        return True
    after = said[i + n : i + n + 1]
    return bool(after) and after[0] in hedges


def _rivals(r: Rules, right: set[str], said: list[str]) -> list[str]:
    """Other values of the kind of ``right`` (a weekday, a month, a season, a year, a day of
    the month) that were said too."""
    kinds = {_kind(r, t) for t in right} - {None, "number"}
    return list(dict.fromkeys(t for t in said if t not in right and _kind(r, t) in kinds))


def _is_year(token: str) -> bool:
    return token.isdigit() and 1900 <= int(token) <= 2099


def _serial(r: Rules, item: Item, said: list[str]) -> Understanding:
    operators = r.lang.operators
    given: list[int] = []
    lowest = min(serial_numbers(item))
    for k, t in enumerate(said):
        if not t.isdigit() or (k > 0 and said[k - 1] in operators):
            continue  # a word, or the "seven" of "minus seven"
        if _unit_of_tens(said, k, given, lowest):
            given[-1] += int(t)  # "ninety... three": a recogniser writes "90, 3"
            continue
        restated = k + 1 < len(said) and said[k + 1] in operators and given[-1:] == [int(t)]
        if not restated:  # "93 minus 7 is 86": that 93 restates the answer before, once
            given.append(int(t))
    return Understanding("answer", serial_points(item, given), tuple(map(str, given)))


def _unit_of_tens(said: list[str], k: int, given: list[int], lowest: int) -> bool:
    """Whether the digit ``said[k]`` is the unit of the round tens just before it, split by a
    pause ("ninety... three", written "90, 3"): a unit alone is never an answer where every
    expected number has two digits, so it finishes the tens a clinician heard."""
    unit, tens = int(said[k]), given[-1] if given else 0
    return (
        lowest >= 10
        and 0 < unit < 10
        and 20 <= tens <= 90
        and tens % 10 == 0
        and said[k - 1] == str(tens)
    )


def touched_in_order(item: Item, targets: list[str]) -> int:
    """The points of the shapes touched on a ``touches`` item: one per stage done in order (the
    most stages touched in the item's order, other touches between them ignored: circle,
    square, then stopping: 2; square, triangle, star: 2)."""
    touched = [t.strip().lower() for t in targets]
    stages = [part.keywords for part in item.parts]
    # the longest common subsequence of the touches and the stages
    best = [[0] * (len(stages) + 1) for _ in range(len(touched) + 1)]
    for i, target in enumerate(touched, 1):
        for j, keywords in enumerate(stages, 1):
            best[i][j] = (
                best[i - 1][j - 1] + 1
                if target in keywords
                else max(best[i - 1][j], best[i][j - 1])
            )
    return best[-1][-1]


def serial_start(item: Item) -> int:
    """The number a ``serial`` item counts from (100 for 93, 86, ...): its first number less
    the step."""
    expected = serial_numbers(item)
    return 2 * expected[0] - expected[1]


def serial_points(item: Item, said: list[int]) -> int:
    """A point per number that is the previous one said (the start for the first) plus the
    step, counting at most as many as the item's parts."""
    expected = serial_numbers(item)
    step = expected[1] - expected[0]
    previous, points = serial_start(item), 0
    if said[:1] == [previous]:  # the start said again ("a hundred, ninety-three, ...")
        said = said[1:]
    for number in said[: len(expected)]:
        points += number == previous + step
        previous = number
    return points
