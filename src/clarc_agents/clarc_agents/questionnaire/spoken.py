"""What was said, as words to match (pure): case, punctuation and hyphens never matter, and
numbers are digits however they were said ("ninety-three", "93"; "twenty twenty five",
"two thousand and twenty five", "2025"; "the first", "1st"). docs/FORMAT.md, "How answers are
understood", gives each rule and its source.

``words(text)`` gives the tokens: lowercase words without accents (apostrophes kept: "don't"),
numbers as digits, ordinals as digits with their suffix ("1st", "24th"). A pause in the text
(a comma, a full stop) ends a number: "twenty, twenty five" is 20 and 25, "twenty twenty five"
is the year 2025.
"""

from __future__ import annotations

import re
import unicodedata

_UNITS = "zero one two three four five six seven eight nine ten eleven twelve thirteen fourteen"
_UNITS += " fifteen sixteen seventeen eighteen nineteen"
UNITS = {w: n for n, w in enumerate(_UNITS.split())}
_TENS = "twenty thirty forty fifty sixty seventy eighty ninety"
TENS = {w: 10 * n for n, w in enumerate(_TENS.split(), 2)}
_ORDINAL_UNITS = "zeroth first second third fourth fifth sixth seventh eighth ninth tenth"
_ORDINAL_UNITS += " eleventh twelfth thirteenth fourteenth fifteenth sixteenth seventeenth"
_ORDINAL_UNITS += " eighteenth nineteenth"
ORDINAL_UNITS = {w: n for n, w in enumerate(_ORDINAL_UNITS.split())}
ORDINAL_TENS = {w[:-1] + "ieth": n for w, n in TENS.items()}  # twentieth, thirtieth...
PAUSE = ","  # a token that ends a number (removed from what ``words`` returns)
_TOKEN = re.compile(r"[a-z0-9']+|[,.;:!?]")
ORDINAL_DIGITS = re.compile(r"^(\d+)(?:st|nd|rd|th)$")


def suffixed(n: int) -> str:
    """1 -> "1st", 22 -> "22nd", 13 -> "13th"."""
    suffix = "th" if 10 <= n % 100 <= 20 else {1: "st", 2: "nd", 3: "rd"}.get(n % 10, "th")
    return f"{n}{suffix}"


def words(text: str, language: str = "en") -> list[str]:
    """The tokens of ``text`` said in ``language`` (see the module's docstring)."""
    text = text.lower()
    if language != "en":
        text = _digits_by_text2num(text, language)
    text = unaccented(text).replace("\u2019", "'").replace("-", " ")
    tokens = [PAUSE if t in ",.;:!?" else t.strip("'") for t in _TOKEN.findall(text)]
    tokens = [t for t in tokens if t]
    if language == "en":
        tokens = _numbers(_hesitations_in_numbers_out(tokens))
    return [t for t in tokens if t != PAUSE]


# Other languages' numbers are made digits by text2num (its rules for Spanish: "noventa y
# tres", "dos mil veintiséis", "la segunda"). English keeps the rules below, which text2num
# does not have: a year said in pairs ("twenty twenty five" is 20 25 there), "a hundred and
# five", a hesitation inside a number.
# An article is no number: "una manzana" is an apple (text2num makes it 1 apple), but "treinta
# y una" and "ciento un" are numbers.
_TENS_ES = "treinta|cuarenta|cincuenta|sesenta|setenta|ochenta|noventa"
_ARTICLE = {"es": re.compile(rf"\b((?:(?:{_TENS_ES}) y |ciento )?)(un|una)\b")}
_KEPT = "qxkeptqx"  # a word of no language: an article text2num must leave alone
# an ordinal as text2num writes it ("2ª", "1º", "1.ᵉʳ"): the tokens' ordinal ("2nd", "1st")
_ORDINAL_MARK = re.compile(r"(\d+)\.?(?:ª|º|ᵉʳ|ᵃ|ᵒ)")


def _digits_by_text2num(text: str, language: str) -> str:
    from text_to_num import alpha2digit  # imported where used: English never needs it

    article = _ARTICLE.get(language)
    if article is not None:
        text = article.sub(lambda m: m[0] if m[1] else m[2] + _KEPT, text)
    text = alpha2digit(text, language, threshold=0).replace(_KEPT, "")
    return _ORDINAL_MARK.sub(lambda m: suffixed(int(m[1])), text)


def unaccented(text: str) -> str:
    """Letters without their accents ("Rocío", "Málaga", "España": "rocio", "malaga", "espana"):
    a recogniser or a typist may write them either way, and a letter the tokens do not know
    would otherwise split the word."""
    return "".join(c for c in unicodedata.normalize("NFKD", text) if not unicodedata.combining(c))


# a sound of hesitation between two words of a number does not end it ("two thousand um twenty
# six" is 2026, as a recogniser writes what the patient said); a pause (a comma) still does
VOCAL_HESITATIONS = frozenset("um uh er erm hmm mm ah eh".split())
_NUMBER_WORDS = frozenset([*UNITS, *TENS, *ORDINAL_UNITS, *ORDINAL_TENS, "hundred", "thousand"])


def _hesitations_in_numbers_out(tokens: list[str]) -> list[str]:
    def in_number(k: int) -> bool:
        before = next((t for t in reversed(tokens[:k]) if t not in VOCAL_HESITATIONS), "")
        after = next((t for t in tokens[k + 1 :] if t not in VOCAL_HESITATIONS), "")
        return before in _NUMBER_WORDS and (after in _NUMBER_WORDS or after == "and")

    return [t for k, t in enumerate(tokens) if t not in VOCAL_HESITATIONS or not in_number(k)]


def _small(tokens: list[str], k: int) -> tuple[int | None, int, bool]:
    """A number under a hundred said at ``tokens[k]`` ("ninety three", "seventh", "twenty
    first"): (its value or None, tokens used, whether it was an ordinal)."""
    word = tokens[k]
    nxt = tokens[k + 1] if k + 1 < len(tokens) else ""
    if word in TENS:
        if nxt in UNITS and 0 < UNITS[nxt] < 10:
            return TENS[word] + UNITS[nxt], 2, False
        if nxt in ORDINAL_UNITS and 0 < ORDINAL_UNITS[nxt] < 10:
            return TENS[word] + ORDINAL_UNITS[nxt], 2, True
        return TENS[word], 1, False
    if word in UNITS:
        return UNITS[word], 1, False
    if word in ORDINAL_UNITS:
        return ORDINAL_UNITS[word], 1, True
    if word in ORDINAL_TENS:
        return ORDINAL_TENS[word], 1, True
    return None, 0, False


def _and_small(tokens: list[str], k: int) -> tuple[int | None, int, bool]:
    """``_small`` after an optional "and" ("a hundred and five")."""
    if k < len(tokens) and tokens[k] == "and":
        value, used, ordinal = _small(tokens, k + 1) if k + 1 < len(tokens) else (None, 0, False)
        return (value, used + 1, ordinal) if value is not None else (None, 0, False)
    return _small(tokens, k) if k < len(tokens) else (None, 0, False)


def _below_thousand(tokens: list[str], k: int) -> tuple[int | None, int, bool]:
    """A number under a thousand from ``tokens[k]``: (value, tokens used, ordinal)."""
    if tokens[k] == "a" and k + 1 < len(tokens) and tokens[k + 1] == "hundred":
        value, used, ordinal = 1, 1, False
    else:
        value, used, ordinal = _small(tokens, k)
    if value is None or ordinal:
        return value, used, ordinal
    if k + used < len(tokens) and tokens[k + used] == "hundred" and 0 < value < 10:
        used += 1
        rest, more, ordinal = _and_small(tokens, k + used)
        return value * 100 + (rest or 0), used + more, ordinal
    return value, used, False


def _number(tokens: list[str], k: int) -> tuple[str | None, int]:
    """The number said from ``tokens[k]`` as a digit token, and the tokens it used."""
    if tokens[k].isdigit():
        # tens in digits and a unit in words, with no pause between: one number as a
        # recogniser writes it ("80 seven" for "eighty seven")
        nxt = tokens[k + 1] if k + 1 < len(tokens) else ""
        tens = int(tokens[k])
        if 20 <= tens <= 90 and tens % 10 == 0 and 0 < UNITS.get(nxt, 0) < 10:
            return str(tens + UNITS[nxt]), 2
        # thousands and the rest in digits, as Whisper writes "two thousand and twenty six"
        after = tokens[k + 2] if k + 2 < len(tokens) else ""
        if 1000 <= tens <= 9000 and tens % 1000 == 0 and nxt == "and" and after.isdigit():
            if int(after) < 1000:
                return str(tens + int(after)), 3
        return tokens[k], 1
    if (m := ORDINAL_DIGITS.match(tokens[k])) is not None:
        return suffixed(int(m[1])), 1
    one = tokens[k] == "a" and k + 1 < len(tokens) and tokens[k + 1] == "thousand"
    value, used, ordinal = (1, 1, False) if one else _below_thousand(tokens, k)
    if value is None:
        return None, 0
    if not ordinal and k + used < len(tokens) and tokens[k + used] == "thousand":
        used += 1
        value *= 1000
        if k + used < len(tokens):
            skip = 1 if tokens[k + used] == "and" and k + used + 1 < len(tokens) else 0
            rest, more, ordinal = _below_thousand(tokens, k + used + skip)
            if rest is not None:
                value, used = value + rest, used + skip + more
    elif not ordinal and used == 1 and value in (19, 20) and k + 1 < len(tokens):
        # a year said in pairs: "nineteen ninety", "twenty twenty five", "twenty oh five"
        nxt = tokens[k + 1]
        if nxt == "oh" and k + 2 < len(tokens) and 0 < UNITS.get(tokens[k + 2], 0) < 10:
            return str(value * 100 + UNITS[tokens[k + 2]]), 3
        rest, more, rest_ordinal = _small(tokens, k + 1)
        if rest is not None and not rest_ordinal and 10 <= rest <= 99:
            return str(value * 100 + rest), 1 + more
    return (suffixed(value) if ordinal else str(value)), used


def _numbers(tokens) -> list[str]:
    tokens = list(tokens)
    out, k = [], 0
    while k < len(tokens):
        number, used = _number(tokens, k)
        if number is None:
            out.append(tokens[k])
            k += 1
        else:
            out.append(number)
            k += used
    return out
