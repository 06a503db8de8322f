"""The TTS output stand-in: "speaks" each sentence for as long as it would take (words at a
rate, scaled), announcing start, end or stopped on clarc/speaker/events; a new sentence or a
stop cuts the current one. With ``wav_dir`` set and espeak-ng installed it also writes real
audio, one WAV per sentence. With ``audio`` it speaks for real: espeak-ng's ``voice`` at
``voice_rate`` words a minute, played in real time (audio cannot be sped up: ``time_scale`` does
not shorten it) as 50 ms chunks on clarc/speaker/audio, each stamped with when it is played; the
sentence ends when its audio does.

ROS Parameters: time_scale (1.0), words_per_second (2.5), wav_dir (""), audio (false), voice
("en-us"), voice_rate (150). Subscriptions: clarc/speaker/say, clarc/speaker/stop. Publishers:
clarc/speaker/events, clarc/speaker/audio (audio_common_msgs/AudioDataStamped, with audio).
"""

from __future__ import annotations

import os
import shutil
import subprocess
import time
from typing import Any

import numpy as np
from std_msgs.msg import String

from clarc_agents import topics
from clarc_agents.asr.audio import RATE
from clarc_agents.asr.audio_topics import CHUNK, CHUNK_SAMPLES, audio_message, audio_publishers
from clarc_sim.devices.sound import Voice, speak
from dsr_graph.ros.dsr_node import DsrNode, main_for
from dsr_graph.ros.json_topics import publish_json, subscribe_json
from dsr_graph.ros.parameters import declare, declare_time_scale, float_param, param
from dsr_graph.ros.qos import qos_stream
from dsr_graph.ros.timers import OneShot


def speaking_time(text: str, words_per_second: float) -> float:
    """Seconds a sentence takes to say: its words at the rate, at least half a second."""
    return max(0.5, len(text.split()) / words_per_second)


class TtsStandIn(DsrNode):
    NAME = "tts"

    @classmethod
    def declare_node_parameters(cls, node) -> None:
        declare_time_scale(node)
        declare(node, "words_per_second", 2.5, "speaking rate", minimum=0.1)
        declare(
            node, "wav_dir", "", "write one WAV per sentence here (needs espeak-ng)", read_only=True
        )
        declare(node, "audio", False, "speak for real on clarc/speaker/audio", read_only=True)
        declare(node, "voice", "en-us", "the robot's espeak-ng voice (audio)", read_only=True)
        declare(
            node,
            "voice_rate",
            150,
            "words a minute (audio)",
            read_only=True,
            minimum=80,
            maximum=450,
        )

    def __init__(self):
        super().__init__()
        self._current: dict[str, Any] | None = None
        self._timer: OneShot | None = None
        self._espeak = shutil.which("espeak-ng")

    def setup(self) -> None:
        if param(self, "wav_dir") and not self._espeak:
            self.get_logger().warning(
                "wav_dir is set but espeak-ng is not installed: no audio files"
            )
        self._events = self.create_publisher(String, topics.SPEAKER, qos_stream())
        self._playing: tuple[np.ndarray, int, float] | None = None  # samples, played, start
        if param(self, "audio"):
            self._voice = Voice(param(self, "voice"), param(self, "voice_rate"))
            speak("ready", self._voice)  # the voice exists (a RuntimeError ends the node now)
            self._audio, self._audio_info = audio_publishers(self, topics.SPEAKER_AUDIO)
            self.create_timer(CHUNK, self._play)
        subscribe_json(self, topics.SPEAKER_SAY, self.on_say, qos_stream())
        subscribe_json(self, topics.SPEAKER_STOP, self.on_stop, qos_stream())

    def _emit(self, sentence: dict[str, Any], event: str) -> None:
        # stamped here: whoever hears of it later (a busy machine) still knows when it happened
        publish_json(
            self._events,
            {
                "id": sentence["id"],
                "text": sentence["text"],
                "event": event,
                "stamp": round(time.time(), 4),
            },
        )

    def on_say(self, request: dict[str, Any]) -> None:
        sentence = {"id": request["id"], "text": str(request["text"])}
        if self._current is not None and self._current["id"] == sentence["id"]:
            # Speech saying it again: it did not hear the start in time (synthesis on a loaded
            # machine took more than its start_patience). The sentence goes on; cutting it
            # ("stopped") ended Speech's say as interrupted and the answer window opened 30 s
            # late, the patient's answer ignored (test_audio, a loaded whole-suite run)
            self._emit(self._current, "start")
            return
        if self._current is not None:
            self._cut("stopped")
        self._current = sentence
        if param(self, "audio"):
            samples = speak(sentence["text"], self._voice)
            self._playing = (samples, 0, time.time())
            self._emit(sentence, "start")
            self._play()
            return
        self._emit(sentence, "start")
        seconds = speaking_time(sentence["text"], float_param(self, "words_per_second"))
        self._timer = OneShot(
            self, seconds * float_param(self, "time_scale"), lambda: self._cut("end")
        )
        self._write_wav(sentence)

    def on_stop(self, request: dict[str, Any]) -> None:
        if self._current is not None and self._current["id"] == request["id"]:
            self._cut("stopped")

    def _play(self) -> None:
        """The chunks of the sentence due by now (the timer may be late: they all go, stamped
        with when they are played); its end when all are out."""
        if self._playing is None:
            return
        samples, played, start = self._playing
        due = min(len(samples), int((time.time() - start) * RATE) + CHUNK_SAMPLES)
        while played < due:
            chunk = samples[played : played + CHUNK_SAMPLES]
            self._audio.publish(audio_message(chunk, start + played / RATE))
            played += len(chunk)
        self._playing = (samples, played, start)
        if played >= len(samples) and time.time() >= start + len(samples) / RATE:
            self._cut("end")

    def _cut(self, event: str) -> None:
        self._playing = None
        if self._timer is not None:
            self._timer.cancel()
            self._timer = None
        sentence, self._current = self._current, None
        if sentence is not None:
            self._emit(sentence, event)

    def _write_wav(self, sentence: dict[str, Any]) -> None:
        wav_dir = param(self, "wav_dir")
        if not wav_dir or not self._espeak:
            return
        os.makedirs(wav_dir, exist_ok=True)
        path = os.path.join(wav_dir, f"sentence-{sentence['id']}.wav")
        subprocess.Popen(
            [self._espeak, "-w", path, sentence["text"]],
            stdout=subprocess.DEVNULL,
            stderr=subprocess.DEVNULL,
        )


main = main_for(TtsStandIn)
