"""The CLARC robot in one process, without ROS, on virtual time: PELEA's executive, the Speech,
Panel and Person grammars with their real processes (``clarc_agents.behaviours``), all on a
``LocalBus`` over the CLARC room, and a patient who answers each item as a test says. The
speaker, the screen and the Kinect are simulated here, as ``clarc_sim`` does over ROS."""

from __future__ import annotations

import logging
from dataclasses import dataclass, field
from datetime import UTC, datetime
from functools import cached_property
from pathlib import Path
from typing import Any

from clarc_agents import definitions
from clarc_agents.behaviours.panel import PanelBehaviour
from clarc_agents.behaviours.speech import SpeechBehaviour
from clarc_agents.grammar_files import load_grammar
from clarc_agents.pelea.questionnaire_executive import QuestionnaireExecutive, QuestionnaireTimes
from clarc_agents.pelea.result_delivery import NOT_YET, REFUSED, STORED
from clarc_agents.questionnaire import confirmation, orientation
from clarc_agents.questionnaire.item_options import awaited_item
from clarc_sim.exceptions import InvalidResult
from clarc_sim.hospital.result_checks import check_result
from clarc_sim.patient import script
from clarc_sim.patient.answering import drawing_for, touches_for, words_for
from dsr_graph.formats.world_files import read_world
from dsr_graph.protocol.local_bus import LocalBus
from dsr_graph.rules.runner import RuleRunner

ROOM = Path(__file__).resolve().parent.parent / "worlds" / "clarc_room.json"
FACE = {"translation": [0.9, 0.0, -0.4], "rotation_euler_xyz": [0.0, 0.0, 0.0]}
WORDS_PER_SECOND = 2.5
REACTION = 1.0  # seconds before the patient answers

log = logging.getLogger("local_clarc")


@dataclass
class Patient:
    """What the patient does: per item, one response per answer window, in order: ``("voice",
    points)``, ``("touch", points)``, ``"silence"``, ``"garbled"`` or ``"skip"``; an item not
    listed earns its maximum, the way it is answered (voice for an option or words, touch for
    shapes or a drawing, the eyes closing for "close your eyes"). ``("voice", points)`` to an
    item of parts says that many right; ``("touch", points)`` touches that many shapes in their
    place, or draws (1) or scribbles (0); ``("shapes", [...])`` touches those shapes, in order;
    ``("eyes", points)`` closes the eyes (1) or not (0).
    ``("unsure", points)`` says the option worth ``points``, heard not for sure (the robot asks
    "I heard: ... Is that right?"); ``("heard", text, confidence)``: the recogniser heard
    ``text`` that sure; ``confirms``: the answers to those questions, in order
    ("yes", "no", "silence", "tap": the Yes button; "yes" once they run out).
    ``leaves``: item -> seconds the patient is away, leaving while that item is introduced."""

    answers: dict[str, list[Any]] = field(default_factory=dict)
    leaves: dict[str, float] = field(default_factory=dict)
    confirms: list[str] = field(default_factory=list)


# every deviation of the test once: a touch, silence twice, words not understood, silence then
# an answer, a skip, the person leaving
EVERY_PATH = Patient(
    answers={
        "bathing": [("touch", 0)],
        "grooming": ["silence", "silence"],
        "dressing": ["garbled", ("voice", 5)],
        "bowels": ["silence", ("voice", 10)],
        "bladder": ["skip"],
        "stairs": [("touch", 5)],
    },
    leaves={"toilet_use": 5.0},
)


class Port:
    """PELEA's Port on the bus; CGAmed's store can be made to fail ``store_failures`` times, and
    refuses what the results store refuses (``check_result``) or anything while ``refuse``."""

    def __init__(self, robot: Robot, link, events=None, stored=None):
        self.robot = robot
        self.link = link
        self.events: list[dict[str, Any]] = [] if events is None else events
        self.notifications: list[str] = []
        self.stored: list[dict[str, Any]] = [] if stored is None else stored  # CGAmed's store
        self.store_failures = 0
        self.refuse = ""  # CGAmed's answer: refused, with this reason
        self.store_calls = 0

    def send(self, tx, on_done=None):
        self.link.send(tx, on_done)

    def after(self, seconds, callback):
        # a timer of a PELEA that died does not fire
        return self.robot.bus.after(seconds, lambda: None if self.link.closed else callback())

    def event(self, **fields):
        self.events.append(dict(fields, t=self.robot.bus.now))

    def notify_clinician(self, message):
        self.notifications.append(message)

    def store_result(self, result, on_done):
        self.store_calls += 1
        if self.refuse:
            self.robot.bus.soon(lambda: on_done(REFUSED, f"result refused: {self.refuse}"))
            return
        if self.store_failures > 0:
            self.store_failures -= 1
            self.robot.bus.soon(lambda: on_done(NOT_YET, "CGAmed did not answer"))
            return
        try:
            check_result(result)
        except InvalidResult as e:
            error = f"result refused: {e}"
            self.robot.bus.soon(lambda: on_done(REFUSED, error))
            return
        key = (result["patient"], result["started"])
        if key not in {(r["patient"], r["started"]) for r in self.stored}:  # stored once
            self.stored.append(result)
        self.robot.bus.soon(lambda: None if self.link.closed else on_done(STORED, ""))

    def dsr_boot(self):
        return self.robot.dsr_boot

    def out_of_reach(self):
        return frozenset(self.robot.bus.unreachable)

    def reach_losses(self):
        return self.robot.bus.reach_losses

    def now(self):
        return datetime.fromtimestamp(self.epoch(), UTC).isoformat()

    def epoch(self):
        return self.robot.epoch()


class Robot:
    def __init__(
        self,
        patient: Patient | None = None,
        present: bool = True,
        test: str = "barthel",
        policy=None,
        language: str = "en",
    ):
        """``policy``: the server's (dsr_graph.model.policy.Policy); by default every write is
        allowed. ``language``: what the test is asked and answered in."""
        self.patient = patient or Patient()
        self.test = test
        self.language = language
        self.bus = LocalBus(read_world(ROOM).graph, **({"policy": policy} if policy else {}))
        self.windows: dict[str, int] = {}
        self.left: set[str] = set()
        self.said: list[str] = []
        self.screen: list[dict[str, Any]] = []
        self._sentences: dict[int, Any] = {}  # sid -> the timer that ends it

        self.person_link = self.bus.agent("/person")
        self.person = RuleRunner(self.person_link, load_grammar("person"), {}, log)
        self.speech_link = self.bus.agent("/speech")
        self.speech = self._speech_behaviour()
        processes = dict(self.speech.processes(), listen=self._listen)
        self.speech_runner = RuleRunner(self.speech_link, load_grammar("speech"), processes, log)
        self.panel_link = self.bus.agent("/panel")
        self.panel = PanelBehaviour(self, log, now=lambda: self.bus.now)
        self.panel_runner = RuleRunner(
            self.panel_link, load_grammar("panel"), self.panel.processes(), log
        )
        self.pelea_link = self.bus.agent("/pelea")
        self.port = Port(self, self.pelea_link)
        self.hle = QuestionnaireExecutive(
            self.port, QuestionnaireTimes(), log, definitions.load(test, language)
        )
        self.pelea_restarts = 0
        self.dsr_boot = "boot-1"  # a test changes it to stand for a restarted DSR server
        for runner in (self.person, self.speech_runner, self.panel_runner):
            runner.setup()
        self.speech_link.add_listener(lambda d, r: self.speech.on_graph(self.speech_link.graph))
        self.pelea_link.add_listener(lambda d, r: self.hle.on_graph(self.pelea_link.graph))
        if present:
            self.person.signal("seen", pose=FACE)
            self.bus.deliver()

    # ------------------------------------------------------------------ running a test
    def run_test(self, patient_name: str = "Carlos", limit: float = 3600.0) -> dict[str, Any]:
        """Press Start and run until the result is stored; the stored result."""
        self.hle.start(self.pelea_link.graph, patient_name)
        self.bus.run(until=lambda: self.finished(), limit=limit)
        assert self.port.stored, f"no result stored; events: {self.port.events[-5:]}"
        return self.port.stored[-1]

    def _speech_behaviour(self) -> SpeechBehaviour:
        link = self.speech_link
        return SpeechBehaviour(
            self,
            self._clock_of(link),
            log,
            now=lambda: self.bus.now,
            epoch=self.epoch,
            graph=lambda: link.graph,
        )

    def epoch(self) -> float:
        """The bus's time as epoch seconds (the Port's and Speech's clock)."""
        return 1_790_000_000 + self.bus.now

    def kinds(self) -> list[str]:
        return [e["event"] for e in self.port.events]

    def _clock_of(self, link):
        """Timers that die with the agent's process."""
        return lambda seconds, callback: self.bus.after(
            seconds, lambda: None if link.closed else callback()
        )

    def restart_speech(self) -> None:
        """Speech's process dies and a new one starts: a new replica, its grammar's recovery."""
        self.speech_link.close()
        self.speech_link = self.bus.agent("/speech")
        self.speech = self._speech_behaviour()
        processes = dict(self.speech.processes(), listen=self._listen)
        self.speech_runner = RuleRunner(self.speech_link, load_grammar("speech"), processes, log)
        self.speech_runner.setup()
        self.speech_link.add_listener(lambda d, r: self.speech.on_graph(self.speech_link.graph))
        self.speech_runner.signal("recover")
        self.speech_runner.step()

    def restart_panel(self) -> None:
        self.panel_link.close()
        self.panel_link = self.bus.agent("/panel")
        self.panel = PanelBehaviour(self, log, now=lambda: self.bus.now)
        self.panel_runner = RuleRunner(
            self.panel_link, load_grammar("panel"), self.panel.processes(), log
        )
        self.panel_runner.setup()
        self.panel_runner.signal("recover")
        self.panel_runner.step()

    def finished(self) -> bool:
        test = self.bus.core.graph.node("test").attrs
        return bool(self.port.stored) and test.get("status") == "finished"

    def restart_pelea(self) -> None:
        """PELEA's process dies (kill -9) and a new one starts with nothing but the DSR."""
        self.pelea_link.close()
        self.pelea_restarts += 1
        self.pelea_link = self.bus.agent("/pelea")
        self.port = Port(self, self.pelea_link, events=self.port.events, stored=self.port.stored)
        self.hle = QuestionnaireExecutive(
            self.port, QuestionnaireTimes(), log, definitions.load(self.test, self.language)
        )
        self.pelea_link.add_listener(lambda d, r: self.hle.on_graph(self.pelea_link.graph))
        self.hle.on_graph(self.pelea_link.graph)  # its first snapshot

    # ------------------------------------------------------------------ the speaker (Speaker)
    def say(self, sid: int, text: str) -> None:
        self.said.append(text)
        seconds = max(0.5, len(text.split()) / WORDS_PER_SECOND)
        self.bus.soon(lambda: self.speech.on_speaker(sid, "start"))
        self._sentences[sid] = self.bus.after(seconds, lambda: self._spoken(sid, "end"))
        self._maybe_leave(text)

    def stop(self, sid: int) -> None:
        timer = self._sentences.pop(sid, None)
        if timer is not None:
            timer.cancel()
            self.bus.soon(lambda: self.speech.on_speaker(sid, "stopped"))

    def _spoken(self, sid: int, event: str) -> None:
        self._sentences.pop(sid, None)
        self.speech.on_speaker(sid, event)

    # ------------------------------------------------------------------ the screen (Screen)
    def display(self, content: dict[str, Any]) -> None:
        self.screen.append(content)

    # ------------------------------------------------------------------ the patient
    @cached_property
    def definition(self):
        """The test as the patient knows it: filled for the robot's today (a test lasts minutes
        of virtual time, within one day) and its place."""
        today = datetime.fromtimestamp(self.epoch()).date()
        known = orientation.values(today, code=self.language)
        return definitions.load(self.test, self.language).filled(known)

    def _maybe_leave(self, text: str) -> None:
        for item, seconds in self.patient.leaves.items():
            position = self.definition.order.index(item) + 1
            if text.startswith(f"Question {position} of") and item not in self.left:
                self.left.add(item)
                self.bus.after(0.5, lambda: self.person.signal("lost"))
                self.bus.after(0.5 + seconds, lambda: self.person.signal("seen", pose=FACE))

    def _listen(self, ctx) -> None:
        """Speech listens (its listen process starts): the patient answers after a moment."""
        self.speech.listen(ctx)
        item = ctx["item"]
        if item == confirmation.KEY:  # "I heard: ... Is that right?"
            asked = self.windows[item] = self.windows.get(item, 0) + 1
            said = (self.patient.confirms[asked - 1 :] or ["yes"])[0]
            if said != "silence":
                self.bus.after(REACTION, lambda: self._confirm(said))
            return
        self.windows[item] = self.windows.get(item, 0) + 1
        spec = self.definition.item(item)
        way = {"voice": "voice", "touch": "touch", "camera": "eyes"}[spec.via[0]]
        responses = self.patient.answers.get(item, [(way, spec.max)])
        response = responses[min(self.windows[item], len(responses)) - 1]
        self.bus.after(REACTION, lambda: self._respond(item, response))

    def _confirm(self, said: str) -> None:
        if said == "tap":  # the Yes button
            self.panel.on_tap(self.panel_runner, self.panel_link.graph, confirmation.YES)
            return
        listening = self.speech.listening
        if listening is not None and listening["item"] == confirmation.KEY:
            yes, no = script.CONFIRMS[self.language]
            self.speech.on_heard(yes if said == "yes" else no)

    def _respond(self, item: str, response: Any) -> None:
        if self.speech.listening is None or self.speech.listening["item"] != item:
            return  # the window closed meanwhile
        if response == "silence":
            return
        if isinstance(response, tuple) and response[0] == "long":
            # a long answer: the voice begins now, its words are heard only after the window's
            # time (as a long answer through a recogniser): ("long", points, seconds)
            spec = self.definition.item(item)
            self.speech_runner.signal("voice", stamp=self.epoch())
            self.bus.after(response[2], lambda: self._answer(spec, "voice", response[1]))
            return
        if isinstance(response, tuple) and response[0] == "unsure":
            option = self.definition.item(item).option(response[1])
            self.speech.on_heard(option.says, confidence=0.3, audio="clips/unsure.wav")
            return
        if isinstance(response, tuple) and response[0] == "heard":  # ("heard", text, confidence)
            clip = f"clips/{item}-{self.windows[item]}.wav"
            self.speech.on_heard(response[1], confidence=response[2], audio=clip)
            return
        if response == "garbled":  # with the clip an asr would have kept
            clip = f"clips/{item}-{self.windows[item]}.wav"
            self.speech.on_heard(script.GARBLED[self.language], audio=clip)
        elif response == "skip":
            self.speech.on_heard("skip this one please")
        else:
            self._answer(self.definition.item(item), *response)

    def _answer(self, spec, way: str, points) -> None:
        graph = self.panel_link.graph
        if way == "shapes":
            for target in points:
                self.panel.on_target(self.panel_runner, self.panel_link.graph, target)
        elif way == "eyes":
            awaited = awaited_item(self.person_link.graph)
            if points and awaited is not None and awaited.kind == "eyes":
                self.person.signal("eyes_closed", points=spec.max)  # as the Person node does
        elif spec.kind == "touches":
            for target in touches_for(spec, points):
                self.panel.on_target(self.panel_runner, graph, target)
        elif spec.kind == "drawing":
            self.panel.on_drawing(self.panel_runner, graph, drawing_for(spec, points))
        elif way == "touch":
            self.panel.on_tap(self.panel_runner, graph, points)
        elif spec.kind in ("words", "serial"):
            self.speech.on_heard(words_for(spec, points))
        else:
            self.speech.on_heard(spec.option(points).says)
