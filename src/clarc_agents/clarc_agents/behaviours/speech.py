"""The Speech agent's processes (paper, Algorithm 3), apart from ROS: ``say`` hands the sentence
to the speaker and finishes when the speaker reports its end (``interrupted`` when stopped);
``stop`` stops every sentence being said; ``listen`` waits for recognised words and maps them to
an option of the item (or skip, or not understood). Rules: ``grammars/speech.yaml``.

The speaker is a device that can miss a request (it was not listening yet) or die in the middle
of a sentence (it forgets it). So a sentence it has not started within ``start_patience`` seconds,
or not ended within twice its expected length, is sent again, from the start; after
``MAX_SENDS`` sends the process finishes (``done``) so the test goes on."""

from __future__ import annotations

import time
from collections.abc import Callable
from typing import Protocol

from clarc_agents.asr.hearing import CONFIRM_CONFIDENCE, MIN_CONFIDENCE
from clarc_agents.behaviours.early_answer import NO_GAP, EarlyAnswer
from clarc_agents.questionnaire.agreement import heard_again
from clarc_agents.questionnaire.answers import understand
from clarc_agents.questionnaire.item_options import hearings, item_in
from dsr_graph.model.graph import Graph
from dsr_graph.rules.runner import ActionContext, Process

MAX_SENDS = 3
WORDS_PER_SECOND = 2.5  # a slow speaker, to bound how long a sentence may take
SLACK = 2.0  # seconds of a real session on top of that
THRESHOLDS = (MIN_CONFIDENCE, CONFIRM_CONFIDENCE)  # Speech's parameters' defaults


class Speaker(Protocol):
    def say(self, sid: int, text: str) -> None: ...
    def stop(self, sid: int) -> None: ...


class Timer(Protocol):
    def cancel(self) -> None: ...


Clock = Callable[[float, Callable[[], None]], Timer]  # after(seconds, callback)


class SpeechBehaviour:
    def __init__(
        self,
        speaker: Speaker,
        after: Clock,
        log,
        scale: float = 1.0,
        start_patience: float = 1.0,
        now: Callable[[], float] = time.monotonic,
        epoch: Callable[[], float] = time.time,
        graph: Callable[[], Graph | None] = lambda: None,
        server_gap: Callable[[], tuple[float, float]] = lambda: NO_GAP,
        thresholds: Callable[[], tuple[float, float]] = lambda: THRESHOLDS,
    ):
        self.speaker = speaker
        self.after = after
        self.log = log
        self.scale = scale
        self.start_patience = start_patience  # seconds of wall time: a matter of processes
        self.epoch = epoch  # when a sentence ended, as the DSR's stamps (a Get Up & Go's "go")
        self.graph = graph  # the agent's replica: the item's options are read from it
        self.thresholds = thresholds  # (min_confidence, confirm_confidence): Speech's parameters
        self.speaking: dict[int, ActionContext] = {}  # sentence id -> the say process
        self.listening: ActionContext | None = None
        self._sends: dict[int, int] = {}
        self._stopping: set[int] = set()  # sentences this agent asked the speaker to stop
        self._watchdogs: dict[int, Timer] = {}
        self._early = EarlyAnswer(now, server_gap)  # words heard just before their window opened

    def processes(self) -> dict[str, Process]:
        return {"say": self.say, "stop": self.stop, "listen": self.listen}

    # -- say / stop -------------------------------------------------------------------------
    def say(self, ctx: ActionContext) -> None:
        sid = int(ctx["sid"])
        self._early.asked()
        self.speaking[sid] = ctx
        self._sends[sid] = 0
        self._send(sid)

    def _send(self, sid: int) -> None:
        self._sends[sid] += 1
        self.speaker.say(sid, self.speaking[sid]["text"])
        self._watch(sid, self.start_patience)

    def _watch(self, sid: int, seconds: float) -> None:
        old = self._watchdogs.pop(sid, None)
        if old is not None:
            old.cancel()
        self._watchdogs[sid] = self.after(seconds, lambda: self._overdue(sid))

    def _overdue(self, sid: int) -> None:
        ctx = self.speaking.get(sid)
        if ctx is None:
            return
        if self._sends[sid] >= MAX_SENDS:
            self.log.warning(f"the speaker never finished sentence {sid}; going on")
            self._end(sid, "done")
            return
        self.log.warning(
            f"the speaker did not start or finish sentence {sid} in time: saying it again"
        )
        self._send(sid)

    def _end(self, sid: int, outcome: str, stamp: float | None = None) -> None:
        ctx = self.speaking.pop(sid)
        self._sends.pop(sid, None)
        self._stopping.discard(sid)
        watchdog = self._watchdogs.pop(sid, None)
        if watchdog is not None:
            watchdog.cancel()
        ctx.finish(outcome, ended_at=round(self.epoch() if stamp is None else stamp, 4))

    def stop(self, ctx: ActionContext) -> str:
        for sid in list(self.speaking):
            self._stopping.add(sid)
            self.speaker.stop(sid)
        return "done"

    def on_speaker(self, sid: int, event: str, stamp: float | None = None) -> None:
        """The speaker reports ``start``, ``end`` or ``stopped`` for sentence ``sid``, ``stamp``
        (epoch s) when it happened if the speaker says (``ended_at`` is then that, not when the
        report came: a Get Up & Go trial is timed from it)."""
        ctx = self.speaking.get(sid)
        if ctx is None:
            return
        if event == "start":
            words = len(str(ctx["text"]).split())
            self._watch(
                sid, 2 * (words / WORDS_PER_SECOND + SLACK) * self.scale + self.start_patience
            )
        elif event == "stopped" and sid not in self._stopping:
            # cut by the speaker itself, not at our request: the sentence is over all the same.
            # As "interrupted" (which only a stop this agent asked for leaves to the stop rule)
            # the robot's speaking edge stayed busy and PELEA waited for it for good
            self.log.warning(f"the speaker cut sentence {sid} on its own: taken as said")
            self._end(sid, "done", stamp)
        elif event in ("end", "stopped"):
            self._end(sid, "done" if event == "end" else "interrupted", stamp)

    # -- listen -----------------------------------------------------------------------------
    def listen(self, ctx: ActionContext) -> None:
        self.listening = ctx
        early = self._early.take(ctx["item"])
        if early is not None:
            text, confidence, audio = early
            self.on_heard(text, confidence=confidence, audio=audio)

    def on_heard(
        self, text: str, item_shown: str = "", confidence: float = 1.0, audio: str = ""
    ) -> None:
        """Words recognised by the ASR (``item_shown``: the item of the sentence on screen;
        ``confidence``: how sure the recogniser is of them: at ``min_confidence`` they are
        understood, at ``confirm_confidence`` an option is confirmed with the patient, and a
        words or serial answer heard before is taken if the two hearings together are sure;
        ``audio``: the clip the recogniser kept of them, the clinician's evidence)."""
        ctx = self.listening
        if ctx is None or ctx.done:
            unless = ""
            if item_shown:  # perhaps an answer to the window about to open: keep it a moment
                self._early.keep((text, confidence, audio), item_shown)
                unless = f" unless a window for {item_shown} opens now"
            self.log.warning(f"heard {text!r} while no answer is awaited: ignored{unless}")
            return
        graph = self.graph()
        item = item_in(graph, ctx["item"]) if graph is not None else None
        if item is not None and "voice" not in item.via:  # touched, drawn or seen, not said
            self.log.info(f"heard {text!r}: item {item.key!r} is not answered by voice")
            return
        self.listening = None
        heard = {"heard": text, "audio": audio, "confidence": round(confidence, 4)}
        if item is None:  # the DSR does not say what the options are: nothing to match
            self.log.warning(f"the DSR has no options for item {ctx['item']!r}: not understood")
            ctx.finish("not_understood", **heard)
            return
        meaning = understand(item, text)
        min_confidence, confirm_confidence = self.thresholds()
        sure = confidence >= min_confidence
        if not sure and meaning.kind == "answer":
            again = heard_again(item, hearings(graph, item.key), text, confidence)
            if again is not None and again[0] >= min_confidence:
                # the patient asked again said what was heard before: two hearings agree
                self.log.info(f"heard {text!r} again (before: {again[1]!r}), {again[0]:.2f} sure")
                sure, heard["confidence"] = True, round(again[0], 4)
        if not sure and confidence >= confirm_confidence and item.kind == "choose":
            if meaning.kind == "answer":  # an option heard, not for sure: PELEA confirms it
                self.log.info(f"heard {text!r}, not for sure: option worth {meaning.points}?")
                ctx.finish("unsure", points=meaning.points, **heard)
                return
        if not sure:
            self.log.info(f"heard {text!r} with too little confidence: not understood")
            ctx.finish("not_understood", **heard)
            return
        if meaning.kind == "answer":
            ctx.finish("answered", points=meaning.points, **heard)
        else:
            ctx.finish(meaning.kind, **heard)

    def on_graph(self, graph: Graph) -> None:
        """The window closed without us (a tap answered, or PELEA stopped waiting): stop
        listening."""
        ctx = self.listening
        if ctx is not None and not ctx.done and graph.edge("person", "answer", "waiting") is None:
            self.listening = None
            ctx.finish("cancelled")
