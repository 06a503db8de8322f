"""The loop with sound (scripts/launch.sh --audio): the robot speaks aloud, the patient answers
aloud in its scenario's voice over babble, the microphone stand-in streams it all, the asr node
recognises it and Speech, PELEA and CGAmed store it. The default Barthel scenario, in a voice
and a room of its own, stores exactly what it stores in text mode: each answer window end to
end with audio, the mumbled first try of dressing not understood and asked again, the silences,
the touches and the patient walking away. Faster than real time where sound allows: --scale 0.7
and the robot speaking at 300 words a minute (the patient at its own pace)."""

import re
import wave
from pathlib import Path

from conftest import needs_espeak
from test_barthel_scenarios import EXPECTED

REPO = Path(__file__).resolve().parents[2]


def test_a_barthel_test_with_sound_stores_what_the_patient_said(tmp_path):
    from ros_processes import launch_scenario

    needs_espeak()
    scenario = tmp_path / "aloud.yaml"
    text = (REPO / "scenarios" / "default.yaml").read_text()
    sound = "voice: {name: en-gb, rate: 170, pitch: 40}\nroom: {noise: babble, snr_db: 20}\n"
    scenario.write_text(text.replace("items:", sound + "items:", 1))
    run, [stored] = launch_scenario(
        scenario, tmp_path, "--audio", "--scale", "0.7", "--voice-rate", "300"
    )
    for key, value in EXPECTED["default.yaml"].items():
        assert stored[key] == value, f"{key}: {stored[key]!r} != {value!r}\n{run.stdout[-4000:]}"
    log = tmp_path / "run" / "log"
    asr = (log / "asr.log").read_text()
    heard = re.findall(r"heard '([^']*)' \(([\d.]+), (\w+)'s search\)", asr)
    assert ("i eat by myself", "feeding") in [(t, item) for t, _, item in heard], asr[-3000:]
    assert "while the robot spoke: its own voice, not an answer" in asr
    with wave.open(str(tmp_path / "run" / "audio" / "microphone.wav")) as w:
        assert (w.getframerate(), w.getnchannels(), w.getsampwidth()) == (16000, 1, 2)
        assert w.getnframes() / 16000 > 60  # the whole run, written as it was streamed
