"""PELEA's executive for a questionnaire test: the Barthel test (paper, Section III-B) or any
other its definition file describes (the MMSE, the Lawton scale), on the loop every test shares
(``hle.py``) with the questionnaire's planning domain (``data/questionnaire_domain.pddl``).

Each item is introduced, its options described, asked, and answered in an answer window (by
voice, on the touch screen, or by what the camera saw); silence or words not understood lead to
the options again and a second window, and a second failure leaves the item unanswered; two
unanswered items call the clinician. Everything needed to go on (the steps done, each item's
attempts and answer, the clinician called, how often the person left) is on the test and item
nodes: a restarted executive asks the item in progress again.
"""

from __future__ import annotations

from dataclasses import dataclass
from datetime import datetime
from typing import Any

from clarc_agents import definitions, test_node
from clarc_agents.definitions import Definition
from clarc_agents.pelea import decision_support
from clarc_agents.pelea.decision_support import Step
from clarc_agents.pelea.hle import (
    CUT_SETTLE,
    REACH_RECHECK,
    HighLevelExecutive,
    Port,
    Times,
)
from clarc_agents.questionnaire import (
    confirmation,
    high_to_low,
    low_to_high,
    monitoring,
    orientation,
    planning,
    sentences,
)
from clarc_agents.questionnaire.record import QuestionnaireRecord
from dsr_graph.model.graph import Graph
from dsr_graph.protocol.presence import PRESENCE_LEASE


@dataclass
class QuestionnaireTimes(Times):
    """The core's times and a questionnaire's own."""

    answer_timeout: float = 8.0  # an answer window


def plan(state: frozenset[str], definition: Definition) -> list[Step]:
    """Decision Support's plan from ``state`` through ``definition``'s items (``NoPlan`` if
    there is none)."""
    problem = planning.problem_pddl(state, definition, planning.GOAL)
    domain = decision_support.domain_path("questionnaire")
    return decision_support.solve(domain, problem, state, planning.GOAL)


@dataclass(frozen=True)
class AnswerWait:
    """An answer (or a failed answer window) for ``item``, in its first or second ``window``."""

    item: str
    window: int
    token: int
    boot: str  # the DSR server that opened the window (its heartbeat's boot)
    losses: int = 0  # how often an agent had gone out of the server's reach when it opened
    confirming: str = ""  # the item whose answer this window confirms (item: confirmation.KEY)


@dataclass
class Overtime:
    """What an answer window that timed out still waits for before it is closed (seconds of
    wall time: these are matters of the network, not of the session)."""

    margin: bool = False  # waited long enough for a cut that had begun to be told
    away: int = 0  # looks spent waiting for agents out of reach to come back
    settled: bool = False  # waited for what agents sent during a cut to arrive


CLOSE_RETRY = 0.2  # seconds before a refused close of an answer window is tried again
# The server tells a cut-off agent a liveliness lease after the cut began (dsr_graph presence):
# a window that times out waits that long before it believes the silence.
PRESENCE_MARGIN = PRESENCE_LEASE + 0.5
CUT_PATIENCE = 60.0  # seconds a window waits for agents out of reach, at most
# seconds after the patient began to speak that a window waits for their words: the longest
# utterance the asr takes (20 s) and its recognition
HEARING_PATIENCE = 30.0
HEARING_RECHECK = 0.5


class QuestionnaireExecutive(HighLevelExecutive):
    KIND = "barthel"  # by default; else the definition's test
    CLOSING = ("say-goodbye", "store-result")
    NEEDS = ("speak", "hear", "show", "take taps")  # nodes/speech_node.py, nodes/panel_node.py
    PROGRESS_FLAGS = {"greet": "greeted", "explain": "explained", "say-goodbye": "said_goodbye"}

    def __init__(
        self,
        port: Port,
        times: QuestionnaireTimes,
        log,
        definition: Definition | None = None,
        place: tuple[str, ...] = orientation.DEFAULT_PLACE,
    ):
        super().__init__(port, times, log)
        # the test as its file says it (by default this executive's KIND's); filled with today's
        # date and the place when it runs
        if definition is None:
            definition = definitions.load(self.KIND)
        # base: the language a Start that names none is asked in
        self.base = self.template = self.definition = definition
        self.KIND = definition.test
        self.place = tuple(place)
        self.record: QuestionnaireRecord | None = None
        # item -> (the option heard not for sure, what was heard, its window): to confirm
        self._unsure: dict[str, tuple[int, str, int]] = {}

    # ------------------------------------------------------------------ the test's own part
    @property
    def languages(self) -> tuple[str, ...]:
        """What a Start may ask this test in."""
        return definitions.languages(self.KIND)

    def _in_language(self, code: str) -> None:
        """The test asked in ``code`` from now on (its definition shipped in it)."""
        if code == self.template.language:
            return
        if code not in self.languages:  # a Start for it is refused (nodes/pelea_node.py)
            self.log.error(f"{self.KIND} is not shipped in {code!r}: asked in the last one")
            return
        self.template = (
            self.base if code == self.base.language else definitions.load(self.KIND, code)
        )

    def _begin(self, graph: Graph, patient: str) -> dict[str, Any]:
        self._in_language(test_node.requested_language(graph, self.base.language))
        self.definition = self._today()
        self.record = QuestionnaireRecord(self.definition, patient, self.port.now())
        self.state = planning.initial_state(test_node.person_present(graph), self.definition)
        return high_to_low.start_test(graph, patient, self.record.started, self.definition)

    def _restore(self, graph: Graph) -> dict[str, Any]:
        """Goes on from the DSR, asking the item in progress again."""
        self._in_language(str(graph.node("test").attrs.get("language", self.base.language)))
        self.definition = self._today()
        self.record = low_to_high.record(graph, self.definition)
        self.state = low_to_high.facts(graph, self.definition)
        item = graph.node("test").attrs.get("item")
        reset = high_to_low.reset_answer(graph)
        if reset is not None:  # a window left open by the previous run: it is asked again
            self.port.send(reset)
            if item in self.record.items and not self.record.items[item].closed:
                self._window_ended(item, "interrupted")
        return {"item": item}

    def _today(self) -> Definition:
        """The test's definition with orientation filled in: today's date (the robot's local
        time) and the place."""
        today = datetime.fromtimestamp(self.port.epoch()).date()
        return self.template.filled(orientation.values(today, self.place, self.template.language))

    def _plan(self, state: frozenset[str]) -> list[Step]:
        return plan(state, self.definition)

    def _person_lost_state(self) -> frozenset[str]:
        """The item in progress starts over when they are back; its answer window closes."""
        if isinstance(self._wait, AnswerWait):
            close = high_to_low.close_answer(self.graph)
            if close is not None:
                self.port.send(close)
        return monitoring.person_lost(self.state, self._current_item())

    def _result(self) -> dict[str, Any]:
        return low_to_high.record(self.graph, self.definition).to_json()

    def _monitor(self) -> str | None:
        """Two unanswered items need the clinician."""
        if (
            not self.record.clinician_called
            and len(self.record.unanswered) >= 2
            and "(clinician-ok)" in self.state
        ):
            self.state = monitoring.clinician_needed(self.state)
            return "two items unanswered: call the clinician"
        return None

    def _current_item(self) -> str:
        return next(
            (f[len("(current ") : -1] for f in self.state if f.startswith("(current ")),
            self.definition.order[0],
        )

    def _check_test_wait(self, graph: Graph, wait: Any) -> None:
        if isinstance(wait, AnswerWait):
            self._on_answer(graph, wait)

    # ------------------------------------------------------------------ the plan's actions
    def _ask_to_sit(self, step: Step) -> None:
        self._say(sentences.sit_down(self.definition))

    def _greet(self, step: Step) -> None:
        self._say(sentences.greet(self.definition, self.record.patient))

    def _explain(self, step: Step) -> None:
        self._say(sentences.explain(self.definition))

    def _introduce(self, step: Step, item: str) -> None:
        self.port.event(event="item", item=item, position=self.definition.order.index(item) + 1)
        self._say(sentences.introduce(self.definition, item))

    def _describe_options(self, step: Step, item: str) -> None:
        self._say(sentences.describe_options(self.definition, item))

    def _nothing_to_describe(self, step: Step, item: str) -> None:
        self._complete(self._token)

    def _ask(self, step: Step, item: str) -> None:
        self._say(sentences.ask(self.definition, item))

    def _options_again(self, step: Step, item: str) -> None:
        self._say(sentences.options_again(self.definition, item))

    def _clarify(self, step: Step, item: str) -> None:
        self._say(sentences.clarify(self.definition, item))

    def _await_answer(self, step: Step, item: str) -> None:
        self._open_window(item, 1)

    def _confirm(self, step: Step, item: str) -> None:
        candidate = self._unsure.get(item)
        if candidate is None:  # lost by a race with a replan: as words not understood
            self._complete(self._token, monitoring.confirmation_failed(self.state, item, 1))
            return
        self._say(confirmation.sentence(self.definition.item(item), candidate[0]))

    def _await_confirmation(self, step: Step, item: str) -> None:
        candidate = self._unsure.get(item)
        self._open_window(item, candidate[2] if candidate else 1, confirming=True)

    def _await_answer_again(self, step: Step, item: str) -> None:
        self._open_window(item, 2)

    def _skip_item(self, step: Step, item: str) -> None:
        self.record.give_up(item)
        self.port.send(high_to_low.record_item(self.record.items[item]))
        self.port.event(event="unanswered", item=item)
        self._complete(self._token)

    def _next_item(self, step: Step, item: str, following: str) -> None:
        self.port.send(high_to_low.current_item(following))
        self._complete(self._token)

    def _call_clinician(self, step: Step) -> None:
        unanswered = self.record.unanswered
        self._tell_clinician(
            f"{self.record.patient} left {len(unanswered)} questions unanswered "
            f"({', '.join(unanswered)}) in the {self.definition.title}: please come and attend.",
            unanswered,
        )
        self._say(sentences.call_clinician(self.definition))

    def _say_goodbye(self, step: Step, item: str) -> None:
        self._say(sentences.goodbye(self.definition, self.record.patient))

    # ------------------------------------------------------------------ answer windows
    def _open_window(self, item: str, window: int, confirming: bool = False) -> None:
        """An answer window for ``item`` (its ``window``-th), or for the confirmation of the
        answer heard to it (the yes or no to confirmation.KEY; no attempt counted)."""
        token = self._token
        if not confirming:
            result = self.record.items[item]
            result.attempts += 1
            self.port.send(high_to_low.record_item(result))
        self.port.event(event="listening", item=item, window=window, confirming=confirming)
        key, confirmed = (confirmation.KEY, item) if confirming else (item, "")

        def opened(r) -> None:
            if token != self._token:
                return
            if not r.accepted:  # the person left at this very moment: _watch_person replans
                self.log.info(f"could not open the answer window: {r.error}")
                return
            wait = AnswerWait(
                key, window, token, self.port.dsr_boot(), self.port.reach_losses(), confirmed
            )
            self._wait = wait
            self._timer = self.port.after(
                self.times(self.times.answer_timeout), lambda: self._answer_timed_out(wait)
            )
            self._check_wait(self.graph)

        self.port.send(high_to_low.open_answer(self.graph, key), opened)

    def _on_answer(self, graph: Graph, wait: AnswerWait) -> None:
        item, window, token = wait.item, wait.window, wait.token
        answer = low_to_high.answer(graph)
        if answer is None:
            return
        self.port.send(high_to_low.consume_answer())
        if answer.item != item:
            return
        if wait.confirming:
            self._confirmed(wait, answer)
            return
        spec = self.definition.item(item)
        valid = (
            answer.points is None and bool(answer.drawing)
            if spec.needs_clinician
            else answer.points in spec.points
        )
        if answer.outcome == "answered" and not valid:
            # written by an agent that did not check it: not an answer to this item
            self.log.warning(f"{answer.points} points is not a score of {item}: not understood")
            answer = low_to_high.Answer(item, "not_understood", heard=f"{answer.points} points")
        if answer.audio:  # the evidence of what was said, for the clinician
            self.record.items[item].audio.append(answer.audio)
        if answer.outcome == "unsure":
            confirmed = self.record.items[item].outcomes.count("unsure")
            if spec.kind != "choose" or confirmed >= confirmation.MOST or not valid:
                # confirmed once already (a test must not drag), or nothing to confirm
                answer = low_to_high.Answer(item, "not_understood", heard=answer.heard)
            else:
                self._unsure[item] = (answer.points, answer.heard, window)
                self._window_ended(item, "unsure", answer.heard)
                self.port.event(event="unsure", item=item, points=answer.points, heard=answer.heard)
                self._complete(token, monitoring.unsure(self.state, item))
                return
        if answer.outcome == "not_understood" and answer.heard and answer.confidence is not None:
            # what was heard, kept for the next window: the same answer heard again is sure
            self.record.items[item].hearings.append((answer.heard, answer.confidence))
        if answer.outcome == "answered":
            self.record.answer(item, answer.points, answer.via, answer.heard, answer.drawing)
            self._window_ended(item, "answered")
            self.port.event(event="answer", item=item, points=answer.points, via=answer.via)
            self._complete(token)
        else:
            self._window_ended(item, answer.outcome, answer.heard)
            self.port.event(event=answer.outcome, item=item, heard=answer.heard, window=window)
            self._complete(
                token, monitoring.window_failed(self.state, item, window, answer.outcome)
            )

    def _confirmed(self, wait: AnswerWait, answer: low_to_high.Answer | None) -> None:
        """The yes or no to the answer read back (None: none came): yes, the option heard
        counts; anything else is words not understood in the window that heard them."""
        item = wait.confirming
        points, heard, window = self._unsure.pop(item, (None, "", wait.window))
        yes = (
            answer is not None
            and answer.outcome == "answered"
            and answer.points == confirmation.YES
            and points is not None
        )
        if yes:
            self.record.answer(item, points, "voice", heard)
            self._window_ended(item, "answered")
            self.port.event(event="answer", item=item, points=points, via="voice", confirmed=True)
            self._complete(wait.token)
            return
        self._window_ended(item, "not_understood", heard)
        self.port.event(event="not_understood", item=item, heard=heard, window=window)
        self._complete(wait.token, monitoring.confirmation_failed(self.state, item, window))

    def _window_ended(self, item: str, outcome: str, heard: str = "") -> None:
        """Written to the item's node: how its window ended, for observers and for a restart. A
        window nobody could be heard in (``interrupted``: no listener took it, or one restarted
        during it, or the server did) is no attempt of the patient's: its count is taken back."""
        result = self.record.items[item]
        result.outcomes.append(outcome)
        if outcome == "interrupted":
            result.attempts = max(0, result.attempts - 1)
        if heard:
            result.heard = heard
        self.port.send(high_to_low.record_item(result))

    def _answer_timed_out(self, wait: AnswerWait, over: Overtime | None = None) -> None:
        item, window, token = wait.item, wait.window, wait.token
        over = over or Overtime()
        if token != self._token or self.graph is None:
            return
        close = high_to_low.close_answer(self.graph, as_read=True)
        if close is None:
            return  # the answer is already there; _check_wait takes it
        partial = low_to_high.touched_so_far(self.graph)

        def later(seconds: float) -> None:
            self._timer = self.port.after(seconds, lambda: self._answer_timed_out(wait, over))

        # The patient is speaking, or their words are being recognised: a careful examiner
        # lets them finish. Bounded by HEARING_PATIENCE after they began (wall time: speech).
        hearing = low_to_high.hearing_since(self.graph)
        if hearing is not None and self.port.epoch() - hearing < HEARING_PATIENCE:
            later(HEARING_RECHECK)
            return
        # A network cut between the hosts: what the patient said may be held on the other side
        # (the listener heard it; its write waits for the link). Keep the window open.
        if not over.margin:
            over.margin = True
            later(PRESENCE_MARGIN)
            return
        away = self.port.out_of_reach()
        if away and over.away * REACH_RECHECK < CUT_PATIENCE:
            if over.away == 0:
                message = f"{', '.join(sorted(away))} out of the DSR's reach: the window stays open"
                self.log.warning(message)
                self.port.event(event="warning", message=message)
            over.away += 1
            later(REACH_RECHECK)
            return
        cut = self.port.reach_losses() != wait.losses
        if cut and not over.settled:
            over.settled = True
            later(CUT_SETTLE)
            return
        # a listener restarted during the window, none ever took it, or one was cut off for a
        # while: what the patient said was not heard, so the window does not count as silence
        interrupted = (
            cut
            or low_to_high.window_interrupted(self.graph)
            or low_to_high.window_untaken(self.graph)
        )

        def closed(r) -> None:
            if not r.accepted:
                # Either an answer won the race (it is in the graph: _check_wait takes it), or
                # the window changed under the close (Speech re-sent can -> waiting after a
                # restart of the server): then close it again as it is now.
                retry = lambda: self._answer_timed_out(wait, over)  # noqa: E731
                self._timer = self.port.after(CLOSE_RETRY, retry)
                return
            if wait.confirming:  # no yes came: the answer heard does not count
                self._confirmed(wait, None)
                return
            # A DSR server that restarted during the window may have lost an answer given then:
            # Speech sends it again, but the close may reach the new server first. Such a
            # window is asked again, never counted as silence.
            if interrupted or self.port.dsr_boot() != wait.boot:
                self._window_ended(item, "interrupted")
                self.port.event(event="window_interrupted", item=item, window=window)
                self._complete(token, monitoring.window_interrupted(self.state, item, window))
                return
            if partial is not None and self.definition.item(item).kind == "touches":
                # fewer stages touched than asked when the window ended: scored as they are
                points, heard = partial
                self.record.answer(item, points, "touch", heard)
                self._window_ended(item, "answered")
                self.port.event(event="answer", item=item, points=points, via="touch")
                self._complete(token)
                return
            if self.definition.item(item).kind == "eyes" and window >= 2:
                # asked twice, the camera never saw the eyes close: not done, 0 points (a
                # first window without it is asked again, as silence is)
                self.record.answer(item, 0, "camera")
                self._window_ended(item, "answered")
                self.port.event(event="answer", item=item, points=0, via="camera")
                self._complete(token)
                return
            self._window_ended(item, "no_answer")
            self.port.event(event="no_answer", item=item, window=window)
            self._complete(token, monitoring.window_failed(self.state, item, window, "no_answer"))

        self.port.send(close, closed)

    # The plan's actions, each with its handler; a test checks it against the PDDL domain.
    ACTIONS = {
        "ask-to-sit": _ask_to_sit,
        "wait-for-person": HighLevelExecutive._wait_for_person,
        "greet": _greet,
        "explain": _explain,
        "introduce": _introduce,
        "describe-options": _describe_options,
        "nothing-to-describe": _nothing_to_describe,
        "ask": _ask,
        "options-again": _options_again,
        "clarify": _clarify,
        "await-answer": _await_answer,
        "await-answer-again": _await_answer_again,
        "confirm": _confirm,
        "await-confirmation": _await_confirmation,
        "skip-item": _skip_item,
        "next-item": _next_item,
        "call-clinician": _call_clinician,
        "say-goodbye": _say_goodbye,
        "store-result": HighLevelExecutive._store_result,
    }
