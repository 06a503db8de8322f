"""The TTS output stand-in: "speaks" each sentence for as long as it would take (words at a
rate, scaled), announcing start, end or stopped on clarc/speaker/events; a new sentence or a
stop cuts the current one. With ``wav_dir`` set and espeak-ng installed it also writes real
audio, one WAV per sentence.

ROS Parameters: time_scale (1.0), words_per_second (2.5), wav_dir (""). Subscriptions:
clarc/speaker/say, clarc/speaker/stop. Publishers: clarc/speaker/events.
"""

from __future__ import annotations

import json
import os
import shutil
import subprocess
from typing import Optional

from clarc_agents import topics
from clarc_agents.agent_node import declare_float, get_float, main_for
from dsr_graph.qos import qos_stream
from rclpy.node import Node
from std_msgs.msg import String


def speaking_time(text: str, words_per_second: float) -> float:
    """Seconds a sentence takes to say: its words at the rate, at least half a second."""
    return max(0.5, len(text.split()) / words_per_second)


class TtsStandIn(Node):
    def __init__(self):
        super().__init__("tts")
        declare_float(self, "time_scale", 1.0, "multiplies every time")
        declare_float(self, "words_per_second", 2.5, "speaking rate")
        self.declare_parameter("wav_dir", "")
        self._events = self.create_publisher(String, topics.SPEAKER, qos_stream())
        self.create_subscription(String, topics.SPEAKER_SAY, self.on_say, qos_stream())
        self.create_subscription(String, topics.SPEAKER_STOP, self.on_stop, qos_stream())
        self._current: Optional[dict] = None
        self._timer = None
        self._espeak = shutil.which("espeak-ng")

    def setup(self) -> None:
        wav_dir = self.get_parameter("wav_dir").value
        if wav_dir and not self._espeak:
            self.get_logger().warning("wav_dir is set but espeak-ng is not installed: no audio files")

    def _emit(self, sentence: dict, event: str) -> None:
        self._events.publish(String(data=json.dumps({"id": sentence["id"], "text": sentence["text"], "event": event})))

    def on_say(self, msg: String) -> None:
        try:
            sentence = json.loads(msg.data)
            sentence = {"id": sentence["id"], "text": str(sentence["text"])}
        except (ValueError, KeyError, TypeError) as e:
            self.get_logger().warning(f"unreadable say request {msg.data!r}: {e}")
            return
        if self._current is not None:
            self._cut("stopped")
        self._current = sentence
        self._emit(sentence, "start")
        seconds = speaking_time(sentence["text"], get_float(self, "words_per_second"))
        self._timer = self.create_timer(seconds * get_float(self, "time_scale"), self._finished)
        self._write_wav(sentence)

    def on_stop(self, msg: String) -> None:
        try:
            ident = json.loads(msg.data)["id"]
        except (ValueError, KeyError, TypeError):
            return
        if self._current is not None and self._current["id"] == ident:
            self._cut("stopped")

    def _finished(self) -> None:
        self._cut("end")

    def _cut(self, event: str) -> None:
        if self._timer is not None:
            self._timer.cancel()
            self.destroy_timer(self._timer)
            self._timer = None
        sentence, self._current = self._current, None
        if sentence is not None:
            self._emit(sentence, event)

    def _write_wav(self, sentence: dict) -> None:
        wav_dir = self.get_parameter("wav_dir").value
        if not wav_dir or not self._espeak:
            return
        os.makedirs(wav_dir, exist_ok=True)
        path = os.path.join(wav_dir, f"sentence-{sentence['id']}.wav")
        subprocess.Popen([self._espeak, "-w", path, sentence["text"]], stdout=subprocess.DEVNULL,
                         stderr=subprocess.DEVNULL)


main = main_for(TtsStandIn)
