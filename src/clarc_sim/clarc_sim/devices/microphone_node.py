"""The microphone stand-in. In text mode (the default) it is microphone and recogniser in one:
what the patient says reaches the robot as recognised text after a short latency (scaled), and
mumbling comes out as mumbling (recognising it is the Speech agent's job). With ``audio`` it is a
microphone only: a continuous stream on clarc/microphone/audio, in real time, of the room's noise
(the scenario's kind, at the level that puts the patient's voice at the scenario's SNR), the
patient's answers spoken by espeak-ng in the scenario's voice, and the robot's own voice as a
microphone on its chest hears it (``robot_gain`` of its output); the ``asr`` node recognises it.

ROS Parameters: time_scale (1.0), latency (0.4 s), audio (false), robot_gain (0.3), wav_file
("": the stream is also written there, audio only).
Subscriptions: clarc/sim/patient/voice, clarc/sim/room (latched), clarc/speaker/audio (audio).
Publishers: clarc/asr (text mode), clarc/microphone/audio (audio_common_msgs/AudioDataStamped,
16 kHz mono S16LE, 50 ms chunks stamped with their capture time; AudioInfo on .../info).
"""

from __future__ import annotations

import os
import time
import wave
from typing import Any

import numpy as np
from audio_common_msgs.msg import AudioDataStamped
from std_msgs.msg import String

from clarc_agents import topics
from clarc_agents.asr.audio import RATE
from clarc_agents.asr.audio_topics import (
    CHUNK,
    CHUNK_SAMPLES,
    audio_message,
    audio_publishers,
    qos_audio,
    samples_of,
)
from clarc_sim import sim_topics
from clarc_sim.devices.sound import RoomNoise, Sources, Voice, noise_level, speak, speech_rms
from dsr_graph.ros.dsr_node import DsrNode, main_for
from dsr_graph.ros.json_topics import publish_json, subscribe_json
from dsr_graph.ros.parameters import declare, declare_time_scale, float_param, param
from dsr_graph.ros.qos import qos_latched, qos_stream
from dsr_graph.ros.timers import OneShot

CALIBRATION = "I am here, and I can hear you well."  # the sentence the SNR is measured on


class MicrophoneStandIn(DsrNode):
    NAME = "microphone"

    @classmethod
    def declare_node_parameters(cls, node) -> None:
        declare_time_scale(node)
        declare(node, "latency", 0.4, "seconds speech recognition takes", minimum=0.0)
        declare(node, "audio", False, "a microphone's audio stream, not text", read_only=True)
        declare(
            node,
            "robot_gain",
            0.3,
            "how loud the robot's own voice is in the microphone (of its output)",
            minimum=0.0,
            maximum=1.0,
        )
        declare(node, "wav_file", "", "the stream is also written here (audio)", read_only=True)

    def __init__(self):
        super().__init__()
        self._sources: Sources | None = None

    def setup(self) -> None:
        subscribe_json(self, sim_topics.PATIENT_VOICE, self.on_voice, qos_stream())
        if not param(self, "audio"):
            self._asr = self.create_publisher(String, topics.ASR, qos_stream())
            return
        self._room = {"noise": "white", "snr_db": 30.0}
        self._set_room(self._room)
        self._audio, self._audio_info = audio_publishers(self, topics.MICROPHONE_AUDIO)
        subscribe_json(self, sim_topics.ROOM, self._set_room, qos_latched())
        self.create_subscription(
            AudioDataStamped, topics.SPEAKER_AUDIO, self.on_robot_audio, qos_audio()
        )
        self._wav = None
        if param(self, "wav_file"):
            os.makedirs(os.path.dirname(os.path.abspath(param(self, "wav_file"))), exist_ok=True)
            self._wav = wave.open(param(self, "wav_file"), "wb")  # its header kept up to date
            self._wav.setnchannels(1)
            self._wav.setsampwidth(2)
            self._wav.setframerate(RATE)
        self._start = time.time()
        self._sent = 0  # stream samples published
        self.create_timer(CHUNK, self._stream)
        self.get_logger().info("microphone up: streaming audio")

    def _set_room(self, room: dict[str, Any]) -> None:
        """The room's noise at the level that puts the patient's voice at its SNR."""
        noise, snr = str(room["noise"]), float(room["snr_db"])
        self._voice = self._patient_voice(room.get("voice"))
        level = noise_level(speech_rms(speak(CALIBRATION, self._patient_voice())), snr)
        fresh = RoomNoise(noise, level, seed=int(time.time()))  # a ValueError names the kind
        self._room = {"noise": noise, "snr_db": snr}
        if self._sources is None:
            self._sources = Sources(fresh)
        else:
            self._sources.noise = fresh
        self.get_logger().info(f"room noise: {noise} at {snr:g} dB below the patient's voice")

    def _patient_voice(self, spec: Any = None) -> Voice:
        if isinstance(spec, list) and len(spec) == 3:
            return Voice(str(spec[0]), int(spec[1]), int(spec[2]))
        return getattr(self, "_voice", Voice())

    def _now_sample(self) -> int:
        return int((time.time() - self._start) * RATE)

    def on_voice(self, voice: dict[str, Any]) -> None:
        text = str(voice["text"])
        if not param(self, "audio"):
            delay = float_param(self, "latency") * float_param(self, "time_scale")
            OneShot(self, delay, lambda: publish_json(self._asr, {"text": text}))
            return
        self._voice = self._patient_voice(voice.get("voice"))
        self._voice.check()  # a ValueError names what is wrong with it
        samples = speak(text, self._voice)
        self._sources.add(max(self._now_sample(), self._sent), samples)
        self.get_logger().info(f"hears the patient say {text!r} ({len(samples) / RATE:.1f} s)")

    def on_robot_audio(self, message: AudioDataStamped) -> None:
        data, stamp = samples_of(message)
        at = max(int((stamp - self._start) * RATE), self._sent)  # late news: heard from now
        gain = float_param(self, "robot_gain")
        self._sources.add(at, np.frombuffer(data, dtype="<i2").astype(float) * gain)

    def _stream(self) -> None:
        """The chunks due by now, each stamped with when its first sample was captured."""
        while self._sent + CHUNK_SAMPLES <= self._now_sample():
            chunk = self._sources.read(self._sent, CHUNK_SAMPLES)
            self._audio.publish(audio_message(chunk, self._start + self._sent / RATE))
            if self._wav is not None:
                self._wav.writeframes(chunk.astype("<i2").tobytes())
            self._sent += CHUNK_SAMPLES

    def close(self) -> None:
        if getattr(self, "_wav", None) is not None:
            self._wav.close()
        super().close()


main = main_for(MicrophoneStandIn)
