"""Which recogniser hears the patient (``asr`` node's ``recogniser`` parameter, ``clarc hear
--recogniser``): Whisper by default, chosen by measurement (BENCHMARKS.md section 9), with
pocketsphinx's second opinion on the words and serial answers it is not sure of, then Whisper
base's on words answers still not sure and Moonshine base's on serial answers still not sure
(``second_opinion.py``: each of the last two loaded the first time it is asked); or
pocketsphinx alone, the one before it, kept to compare. Each loads its model when made (a
second or two) and gives ``hear_item(samples, item) -> (Heard, how)``."""

from __future__ import annotations

RECOGNISERS = ("whisper", "pocketsphinx")
DEFAULT = "whisper"
# Speech's default min_confidence: a text heard less sure than this is not understood
MIN_CONFIDENCE = 0.5
# and its confirm_confidence: an option heard at least this sure is confirmed with the patient
CONFIRM_CONFIDENCE = 0.2


def open_recogniser(name: str = DEFAULT, language: str = "en"):
    """The recogniser called ``name`` for answers in ``language``; ValueError naming the choices
    for any other. pocketsphinx's model is American English: in another language Whisper hears
    alone (the multilingual base), and pocketsphinx is no choice."""
    if name not in RECOGNISERS:
        raise ValueError(f"recogniser {name!r}: one of {', '.join(RECOGNISERS)}")
    if name == "pocketsphinx" and language != "en":
        raise ValueError(f"pocketsphinx hears English only, not {language!r}: use whisper")
    if name == "whisper":
        from clarc_agents.asr.whisper import WhisperRecogniser

        if language != "en":
            return WhisperRecogniser(language)
        from clarc_agents.asr.models import WHISPER_BASE
        from clarc_agents.asr.recogniser import Recogniser
        from clarc_agents.asr.second_opinion import SecondOpinion

        def larger() -> WhisperRecogniser:
            return WhisperRecogniser(language, model=WHISPER_BASE)

        def other():
            from clarc_agents.asr.moonshine import MoonshineRecogniser

            return MoonshineRecogniser()

        return SecondOpinion(WhisperRecogniser(), Recogniser(), MIN_CONFIDENCE, larger, other)
    from clarc_agents.asr.recogniser import Recogniser

    return Recogniser()
