"""The TTS output stand-in: "speaks" each sentence for as long as it would take (words at a
rate, scaled), announcing start, end or stopped on clarc/speaker/events; a new sentence or a
stop cuts the current one. With ``wav_dir`` set and espeak-ng installed it also writes real
audio, one WAV per sentence.

ROS Parameters: time_scale (1.0), words_per_second (2.5), wav_dir (""). Subscriptions:
clarc/speaker/say, clarc/speaker/stop. Publishers: clarc/speaker/events.
"""

from __future__ import annotations

import os
import shutil
import subprocess
import time
from typing import Any

from std_msgs.msg import String

from clarc_agents import topics
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
        if self._current is not None:
            self._cut("stopped")
        self._current = sentence
        self._emit(sentence, "start")
        seconds = speaking_time(sentence["text"], float_param(self, "words_per_second"))
        self._timer = OneShot(
            self, seconds * float_param(self, "time_scale"), lambda: self._cut("end")
        )
        self._write_wav(sentence)

    def on_stop(self, request: dict[str, Any]) -> None:
        if self._current is not None and self._current["id"] == request["id"]:
            self._cut("stopped")

    def _cut(self, event: str) -> None:
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
