"""The asr agent (``--audio``): hears the patient in the microphone's stream. It cuts the stream
into utterances (voice activity detection, asr/utterances.py), recognises each biased by what
the DSR says is expected now (the awaited item, else the one on the screen just before its
window opens): with Whisper, the item's sentences as the decoder's previous text and a choose
item's options rescored (asr/whisper.py, asr/expectations.py); with pocketsphinx, a search
restricted to them (asr/searches.py). An item in a language other than English is heard by
the multilingual Whisper base, loaded when the first such item is heard. It publishes what it
heard, with its confidence and when it was said, on clarc/asr: Speech understands it and writes
the answer, as from any recogniser.
What the robot said itself (its speaker's start and end) is never published, nor what the
recogniser's guards call no speech. It writes nothing in the DSR: it reads it. Recognition runs
on a thread of its own, so the stream is never held up.

Each utterance it publishes is kept as a WAV clip in ``clips_dir`` (asr/clips.py), its path
sent with the text: the clinician's evidence for an answer the robot could not understand.

ROS Parameters: setup_timeout (20), recogniser ("whisper" or "pocketsphinx", read-only),
clips_dir (read-only; "" is $ROS_HOME/clarc/clips, ~/.ros/clarc/clips without ROS_HOME).
Subscriptions: clarc/microphone/audio (audio_common_msgs/AudioDataStamped, 16 kHz mono S16LE),
clarc/speaker/events, the DSR. Publishers: clarc/asr/voice ({"start"}: the patient began to
speak, not the robot), clarc/asr ({"text", "confidence", "start", "end", "recogniser", "audio"
(the clip's path), "snr_db" (the voice's level over the room), and "transcript" when a choose
item's options were rescored: what free decoding wrote}).
"""

from __future__ import annotations

import queue
import threading
from typing import Any

from audio_common_msgs.msg import AudioDataStamped
from std_msgs.msg import String

from clarc_agents import topics
from clarc_agents.asr.audio_topics import qos_audio, samples_of
from clarc_agents.asr.clips import Clips, default_folder
from clarc_agents.asr.hearing import DEFAULT, RECOGNISERS, open_recogniser
from clarc_agents.asr.utterances import RobotSpeech, Utterance, Utterances
from clarc_agents.definitions import Item
from clarc_agents.questionnaire.item_options import awaited_item, item_in, item_on_screen
from dsr_graph.ros.agent import DsrAgent
from dsr_graph.ros.dsr_node import DsrNode, main_for
from dsr_graph.ros.json_topics import publish_json, subscribe_json
from dsr_graph.ros.parameters import declare, declare_setup_timeout, float_param, param
from dsr_graph.ros.qos import qos_stream

STOP = None  # what the recognition thread is given to end


class AsrAgent(DsrNode):
    NAME = "asr"

    @classmethod
    def declare_node_parameters(cls, node) -> None:
        declare_setup_timeout(node, 20.0)
        declare(
            node,
            "recogniser",
            DEFAULT,
            f"the speech recogniser: {' or '.join(RECOGNISERS)}",
            read_only=True,
        )
        declare(node, "clips_dir", "", "where the clips of what was said are kept", read_only=True)

    def __init__(self):
        super().__init__()
        self.dsr = DsrAgent()
        self._utterances = Utterances()
        self._robot = RobotSpeech()
        self._work: queue.Queue = queue.Queue()
        self._thread: threading.Thread | None = None

    def setup(self) -> None:
        self.dsr.describe(can_do=["recognise speech"], listens_to=[topics.MICROPHONE_AUDIO])
        self.dsr.setup(self, timeout_sec=float_param(self, "setup_timeout"))
        # English's now (a second or two), another language's when an item in it is heard
        self._recognisers = {"en": open_recogniser(str(param(self, "recogniser")))}
        self._language = "en"  # of the last item: what is said between items is heard in it
        self._clips = Clips(str(param(self, "clips_dir")) or default_folder())
        self._asr = self.create_publisher(String, topics.ASR, qos_stream())
        self._voice = self.create_publisher(String, topics.ASR_VOICE, qos_stream())
        subscribe_json(self, topics.SPEAKER, self.on_speaker, qos_stream())
        self.create_subscription(
            AudioDataStamped, topics.MICROPHONE_AUDIO, self.on_audio, qos_audio()
        )
        self._thread = threading.Thread(target=self._recognise, name="asr", daemon=True)
        self._thread.start()
        self.get_logger().info("asr up: listening to the microphone")

    def on_speaker(self, event: dict[str, Any]) -> None:
        stamp = event.get("stamp")
        if isinstance(stamp, (int, float)) and not isinstance(stamp, bool):
            self._robot.event(str(event.get("event")), float(stamp))

    def on_audio(self, message: AudioDataStamped) -> None:
        data, stamp = samples_of(message)  # a ValueError is logged, the chunk dropped
        before = self._utterances.under_way
        ended = self._utterances.feed(data, stamp)
        began = self._utterances.under_way
        if began is not None and began != before and not self._robot.speaking_at(began):
            # the patient is speaking: the window waits for the words (Speech marks it)
            publish_json(self._voice, {"start": round(began, 3)})
        for utterance in ended:
            if self._robot.spoke_over(utterance.start, utterance.end):
                self.get_logger().info(
                    f"{utterance.end - utterance.start:.1f} s of speech while the robot spoke: "
                    "its own voice, not an answer"
                )
                continue
            self._work.put((utterance, self._expected()))

    def _expected(self) -> Item | None:
        """The item whose answer is awaited, else the one on the screen (its window about to
        open), as the DSR says it is answered; None: nothing is expected (free search)."""
        if not self.dsr.synced:
            return None
        graph = self.dsr.graph
        item = awaited_item(graph)
        if item is None:
            key = item_on_screen(graph)
            item = item_in(graph, key) if key else None
        return item

    def _recognise(self) -> None:
        while (job := self._work.get()) is not STOP:
            utterance, item = job
            try:
                self._hear(utterance, item)
            except Exception as e:  # noqa: BLE001 - a bad utterance never ends the thread
                self.get_logger().error(f"recognition failed: {e!r}")

    def _recogniser_for(self, item: Item | None):
        """The recogniser for the item's language (loaded the first time: on this thread, so
        the stream never waits)."""
        self._language = item.language if item is not None else self._language
        if self._language not in self._recognisers:
            self.get_logger().info(f"loading the recogniser for {self._language!r}")
            name = str(param(self, "recogniser"))
            self._recognisers[self._language] = open_recogniser(name, self._language)
        return self._recognisers[self._language]

    def _hear(self, utterance: Utterance, item: Item | None) -> None:
        recogniser = self._recogniser_for(item)
        heard, how = recogniser.hear_item(utterance.samples, item)
        if not heard.text:
            self.get_logger().info("speech, but no words recognised in it")
            return
        said = {
            "text": heard.text,
            "confidence": round(heard.confidence, 3),
            "start": round(utterance.start + heard.start, 3),
            "end": round(utterance.start + heard.end, 3),
            "recogniser": recogniser.name,
            "audio": self._clips.keep(utterance.samples, utterance.start),
        }
        if heard.transcript:
            said["transcript"] = heard.transcript
        if heard.confirmed_by:
            said["confirmed_by"] = heard.confirmed_by
        if heard.snr_db is not None:
            said["snr_db"] = round(heard.snr_db, 1)
        what = "free" if how == "free" else f"{item.key}'s {how}"
        room = "" if heard.snr_db is None else f", {heard.snr_db:.0f} dB over the room"
        self.get_logger().info(
            f"heard {heard.text!r} ({heard.confidence:.2f}, {what} search{room})"
        )
        publish_json(self._asr, said)

    def close(self) -> None:
        if self._thread is not None:
            self._work.put(STOP)
            self._thread.join(timeout=10.0)
        super().close()


main = main_for(AsrAgent)
