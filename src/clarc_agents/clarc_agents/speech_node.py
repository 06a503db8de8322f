"""The Speech agent (paper, Algorithm 3): says the sentence PELEA puts on test -is_in->
test_part through the TTS, stops at once when the person it talks to leaves, and listens for
answers, mapping recognised words to the item's options. Its rules: grammars/speech.yaml.

Publishers: clarc/speaker/say, clarc/speaker/stop. Subscriptions: clarc/speaker/events,
clarc/asr. Plus the DSR topics (dsr_graph.agent).
"""

from __future__ import annotations

import json
from typing import Dict, Optional

from dsr_graph.qos import qos_stream
from dsr_graph.rule_agent import ActionContext, Process
from std_msgs.msg import String

from . import topics
from .agent_node import GrammarAgentNode, main_for
from .answers import understand
from .barthel import BY_KEY


class SpeechAgent(GrammarAgentNode):
    GRAMMAR = "speech"

    def __init__(self):
        super().__init__("speech")
        self._say = self.create_publisher(String, topics.SPEAKER_SAY, qos_stream())
        self._stop = self.create_publisher(String, topics.SPEAKER_STOP, qos_stream())
        self.create_subscription(String, topics.SPEAKER, self.on_speaker, qos_stream())
        self.create_subscription(String, topics.ASR, self.on_asr, qos_stream())
        self.speaking: Dict[int, ActionContext] = {}  # sentence id -> the say process
        self.listening: Optional[ActionContext] = None

    def processes(self) -> Dict[str, Process]:
        return {"say": self.say, "stop": self.stop, "listen": self.listen}

    def setup(self) -> None:
        super().setup()
        self.dsr.add_listener(self._on_graph)

    # -- say / stop -------------------------------------------------------------------------
    def say(self, ctx: ActionContext) -> None:
        sid = int(ctx["sid"])
        self.speaking[sid] = ctx
        self._say.publish(String(data=json.dumps({"id": sid, "text": ctx["text"]})))

    def stop(self, ctx: ActionContext) -> str:
        for sid in list(self.speaking):
            self._stop.publish(String(data=json.dumps({"id": sid})))
        return "done"

    def on_speaker(self, msg: String) -> None:
        try:
            event = json.loads(msg.data)
            ctx = self.speaking.get(int(event["id"]))
        except (ValueError, KeyError, TypeError) as e:
            self.get_logger().warning(f"unreadable speaker event {msg.data!r}: {e}")
            return
        if ctx is None or event.get("event") not in ("end", "stopped"):
            return
        del self.speaking[int(event["id"])]
        ctx.finish("done" if event["event"] == "end" else "interrupted")

    # -- listen -----------------------------------------------------------------------------
    def listen(self, ctx: ActionContext) -> None:
        self.listening = ctx

    def on_asr(self, msg: String) -> None:
        try:
            text = str(json.loads(msg.data)["text"])
        except (ValueError, KeyError, TypeError) as e:
            self.get_logger().warning(f"unreadable ASR message {msg.data!r}: {e}")
            return
        ctx = self.listening
        if ctx is None or ctx.done:
            self.get_logger().info(f"heard {text!r} while not listening")
            return
        self.listening = None
        meaning = understand(BY_KEY[ctx["item"]], text)
        if meaning.kind == "answer":
            ctx.finish("answered", points=meaning.points, heard=text)
        else:
            ctx.finish(meaning.kind, heard=text)

    def _on_graph(self, deltas, resynced) -> None:
        # The window closed without us (a tap answered, or PELEA stopped waiting): stop listening.
        ctx = self.listening
        if ctx is not None and not ctx.done and self.dsr.graph.edge("person", "answer", "waiting") is None:
            self.listening = None
            ctx.finish("cancelled")


main = main_for(SpeechAgent)
