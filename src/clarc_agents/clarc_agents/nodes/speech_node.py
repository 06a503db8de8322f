"""The Speech agent (paper, Algorithm 3): says the sentence PELEA puts on test -is_in->
test_part through the TTS, stops at once when the person it talks to leaves, and listens for
answers, mapping recognised words to the item's options. Its rules: grammars/speech.yaml.

ROS Parameters: min_confidence (0.5: a recognised text less sure than this is not understood,
and the item is asked again), confirm_confidence (0.2: an option heard at least this sure, but
under min_confidence, is confirmed with the patient first; a words or serial answer under it is
taken if it was heard the same before, questionnaire/agreement.py). Publishers: clarc/speaker/say,
clarc/speaker/stop, and REP-155's
/humans/voices/tracked and /humans/voices/anonymous_speaker/speech (what was heard:
nodes/humans_topics.py).
Subscriptions: clarc/speaker/events, clarc/asr ({"text", "confidence", "audio": the clip's
path, kept on the answer for the clinician}), clarc/asr/voice ({"start"}: the patient began
to speak; marked on the open window, which PELEA then keeps open for the words). Plus the DSR
topics (dsr_graph.ros.agent).
"""

from __future__ import annotations

from typing import Any

from std_msgs.msg import String

from clarc_agents import topics
from clarc_agents.asr.hearing import CONFIRM_CONFIDENCE, MIN_CONFIDENCE
from clarc_agents.behaviours.speech import SpeechBehaviour
from clarc_agents.nodes.grammar_agent import GrammarAgentNode
from clarc_agents.nodes.humans_topics import SpeechHumans
from clarc_agents.questionnaire.item_options import item_on_screen
from dsr_graph.ros.dsr_node import main_for
from dsr_graph.ros.json_topics import publish_json, subscribe_json
from dsr_graph.ros.parameters import declare, float_param
from dsr_graph.ros.qos import qos_stream
from dsr_graph.ros.timers import OneShot
from dsr_graph.rules.runner import Process


class SpeechAgent(GrammarAgentNode):
    GRAMMAR = "speech"

    NAME = "speech"

    @classmethod
    def declare_node_parameters(cls, node) -> None:
        super().declare_node_parameters(node)
        declare(
            node,
            "min_confidence",
            MIN_CONFIDENCE,
            "a recognised text less sure than this is not understood (asked again)",
            minimum=0.0,
            maximum=1.0,
        )
        declare(
            node,
            "confirm_confidence",
            CONFIRM_CONFIDENCE,
            "an option heard at least this sure (but under min_confidence) is confirmed: "
            '"I heard: ... Is that right?"',
            minimum=0.0,
            maximum=1.0,
        )

    def __init__(self):
        super().__init__()
        self.behaviour = SpeechBehaviour(
            self,
            lambda seconds, callback: OneShot(self, seconds, callback),
            self.get_logger(),
            scale=self.scale,
            server_gap=lambda: self.dsr.server_gap,
            graph=lambda: self.dsr.graph,
            thresholds=lambda: (
                float_param(self, "min_confidence"),
                float_param(self, "confirm_confidence"),
            ),
        )

    def processes(self) -> dict[str, Process]:
        return self.behaviour.processes()

    def setup(self) -> None:
        self._say = self.create_publisher(String, topics.SPEAKER_SAY, qos_stream())
        self._stop = self.create_publisher(String, topics.SPEAKER_STOP, qos_stream())
        subscribe_json(self, topics.SPEAKER, self.on_speaker, qos_stream())
        self._humans = SpeechHumans(self)
        subscribe_json(self, topics.ASR, self.on_asr, qos_stream())
        subscribe_json(self, topics.ASR_VOICE, self.on_voice, qos_stream())
        # ready once the recogniser (or the microphone that is one) is heard: an answer said
        # before that would go to no one
        self.dsr.describe(can_do=["speak", "hear"], listens_to=[topics.ASR])
        super().setup()
        self.dsr.add_listener(lambda deltas, resynced: self.behaviour.on_graph(self.dsr.graph))

    # -- the speaker (Speaker protocol) and the ASR ------------------------------------------
    def say(self, sid: int, text: str) -> None:
        publish_json(self._say, {"id": sid, "text": text})

    def stop(self, sid: int) -> None:
        publish_json(self._stop, {"id": sid})

    def on_speaker(self, event: dict[str, Any]) -> None:
        stamp = event.get("stamp")
        stamp = (
            float(stamp)
            if isinstance(stamp, (int, float)) and not isinstance(stamp, bool)
            else None
        )
        self.behaviour.on_speaker(int(event["id"]), str(event.get("event")), stamp)

    def on_voice(self, message: dict[str, Any]) -> None:
        """The patient began to speak: the open window is marked as hearing (rule hearing)."""
        stamp = message["start"]
        if isinstance(stamp, bool) or not isinstance(stamp, (int, float)):
            raise ValueError(f"start must be a time (epoch s), got {stamp!r}")
        if self.runner is not None:
            self.runner.signal("voice", stamp=float(stamp))

    def on_asr(self, message: dict[str, Any]) -> None:
        text = message["text"]
        if not isinstance(text, str):
            raise ValueError(f"recognised text must be a string, got {type(text).__name__}")
        confidence = message.get("confidence", 1.0)  # the stand-in's text is what was said
        if (
            isinstance(confidence, bool)
            or not isinstance(confidence, (int, float))
            or not 0.0 <= confidence <= 1.0
        ):
            raise ValueError(f"confidence must be a number from 0 to 1, got {confidence!r}")
        audio = message.get("audio", "")
        if not isinstance(audio, str) or len(audio) > 4096:
            raise ValueError(f"audio must be a clip's path, got {audio!r:.100}")
        self._humans.heard(text, confidence)
        item_shown = item_on_screen(self.dsr.graph)
        self.behaviour.on_heard(text, item_shown, confidence=float(confidence), audio=audio)


main = main_for(SpeechAgent)
