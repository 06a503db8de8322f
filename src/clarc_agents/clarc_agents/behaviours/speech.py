"""The Speech agent's processes (paper, Algorithm 3), apart from ROS: ``say`` hands the sentence
to the speaker and finishes when the speaker reports its end (``interrupted`` when stopped);
``stop`` stops every sentence being said; ``listen`` waits for recognised words and maps them to
an option of the item (or skip, or not understood). Rules: ``grammars/speech.yaml``."""

from __future__ import annotations

from typing import Protocol

from clarc_agents.barthel.answers import understand
from clarc_agents.barthel.items import BY_KEY
from dsr_graph.model.graph import Graph
from dsr_graph.rules.runner import ActionContext, Process


class Speaker(Protocol):
    def say(self, sid: int, text: str) -> None: ...
    def stop(self, sid: int) -> None: ...


class SpeechBehaviour:
    def __init__(self, speaker: Speaker, log):
        self.speaker = speaker
        self.log = log
        self.speaking: dict[int, ActionContext] = {}  # sentence id -> the say process
        self.listening: ActionContext | None = None

    def processes(self) -> dict[str, Process]:
        return {"say": self.say, "stop": self.stop, "listen": self.listen}

    # -- say / stop -------------------------------------------------------------------------
    def say(self, ctx: ActionContext) -> None:
        sid = int(ctx["sid"])
        self.speaking[sid] = ctx
        self.speaker.say(sid, ctx["text"])

    def stop(self, ctx: ActionContext) -> str:
        for sid in list(self.speaking):
            self.speaker.stop(sid)
        return "done"

    def on_speaker(self, sid: int, event: str) -> None:
        """The speaker reports ``start``, ``end`` or ``stopped`` for sentence ``sid``."""
        ctx = self.speaking.get(sid)
        if ctx is None or event not in ("end", "stopped"):
            return
        del self.speaking[sid]
        ctx.finish("done" if event == "end" else "interrupted")

    # -- listen -----------------------------------------------------------------------------
    def listen(self, ctx: ActionContext) -> None:
        self.listening = ctx

    def on_heard(self, text: str) -> None:
        """Words recognised by the ASR."""
        ctx = self.listening
        if ctx is None or ctx.done:
            self.log.info(f"heard {text!r} while not listening")
            return
        self.listening = None
        meaning = understand(BY_KEY[ctx["item"]], text)
        if meaning.kind == "answer":
            ctx.finish("answered", points=meaning.points, heard=text)
        else:
            ctx.finish(meaning.kind, heard=text)

    def on_graph(self, graph: Graph) -> None:
        """The window closed without us (a tap answered, or PELEA stopped waiting): stop
        listening."""
        ctx = self.listening
        if ctx is not None and not ctx.done and graph.edge("person", "answer", "waiting") is None:
            self.listening = None
            ctx.finish("cancelled")
