"""The High Level Executive: runs a questionnaire test, the Barthel test (paper, Section III-B)
or any other its definition file describes (the MMSE, the Lawton scale).

Crash-only: Start arrives as a request in the DSR, and everything needed to go on (the steps
done, each item's attempts and answer, the clinician called, how often the person left) is
written to the DSR as the test runs; an executive that finds a running test there (it was
restarted) rebuilds its state from it and replans, asking the item in progress again. The
stored result is read from the DSR, never from memory alone. Pure logic behind a small
``Port`` (send a transaction, start a timer, report, store the result), so the whole course of
a test can be driven by unit tests with a local graph; ``node.py`` connects it to ROS.

Loop: plan from the current state (Decision Support) -> execute the first action (HighToLow)
-> watch the DSR (LowToHigh) -> on completion apply the action's effects and go on; on a
deviation (no answer, words not understood, the person left, two items unanswered) record it
as facts (Monitoring) and plan again from there.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from datetime import datetime
from typing import Any, Protocol

from clarc_agents import definitions
from clarc_agents.definitions import Definition
from clarc_agents.pelea import decision_support, high_to_low, low_to_high, monitoring
from clarc_agents.pelea.decision_support import Step
from clarc_agents.pelea.result_delivery import STORED, deliver
from clarc_agents.questionnaire import orientation, sentences
from clarc_agents.questionnaire.record import QuestionnaireRecord
from dsr_graph.model.graph import Graph
from dsr_graph.protocol.presence import PRESENCE_LEASE

# Actions that must not be broken off when the person leaves: the test is over by then.
CLOSING = ("say-goodbye", "store-result")
# Steps whose completion is written on the test node (the other steps leave their own trace).
PROGRESS_FLAGS = {"greet": "greeted", "explain": "explained", "say-goodbye": "said_goodbye"}


@dataclass
class Times:
    """Every time of the flow, in seconds of a real session; ``scale`` shrinks them together."""

    scale: float = 1.0
    answer_timeout: float = 8.0  # an answer window
    words_per_second: float = 2.5  # to bound how long a sentence may take
    sentence_slack: float = 5.0
    store_retry: float = 2.0

    def __call__(self, seconds: float) -> float:
        return seconds * self.scale

    def sentence_timeout(self, text: str) -> float:
        return self(3 * len(text.split()) / self.words_per_second + self.sentence_slack) + 2.0


# ------------------------------------------------------------------ what a step waits for
@dataclass(frozen=True)
class SentenceWait:
    """Speech and Panel both finished sentence ``sid``."""

    sid: int
    token: int


@dataclass(frozen=True)
class PersonWait:
    """The person is in front of the robot again."""

    token: int


@dataclass(frozen=True)
class AnswerWait:
    """An answer (or a failed answer window) for ``item``, in its first or second ``window``."""

    item: str
    window: int
    token: int
    boot: str  # the DSR server that opened the window (its heartbeat's boot)
    losses: int = 0  # how often an agent had gone out of the server's reach when it opened


@dataclass
class Overtime:
    """What an answer window that timed out still waits for before it is closed (seconds of
    wall time: these are matters of the network, not of the session)."""

    margin: bool = False  # waited long enough for a cut that had begun to be told
    away: int = 0  # looks spent waiting for agents out of reach to come back
    settled: bool = False  # waited for what agents sent during a cut to arrive


Wait = SentenceWait | PersonWait | AnswerWait


CLOSE_RETRY = 0.2  # seconds before a refused close of an answer window is tried again
# The server tells a cut-off agent a liveliness lease after the cut began (dsr_graph presence):
# a window that times out waits that long before it believes the silence.
PRESENCE_MARGIN = PRESENCE_LEASE + 0.5
REACH_RECHECK = 0.5  # seconds between looks at whether agents out of reach are back
CUT_PATIENCE = 60.0  # seconds a window waits for agents out of reach, at most
# seconds for what agents sent during a cut to arrive once it ends (DDS delivers what it held at
# once; an agent sends again a request unanswered for 3 s)
CUT_SETTLE = 4.0


class Timer(Protocol):
    def cancel(self) -> None: ...


class Port(Protocol):
    def send(self, tx: dict[str, Any], on_done: Callable[[Any], None] | None = None) -> None: ...
    def after(self, seconds: float, callback: Callable[[], None]) -> Timer: ...
    def event(self, **fields: Any) -> None: ...
    def notify_clinician(self, message: str) -> None: ...
    def store_result(  # on_done(result_delivery.STORED | REFUSED | NOT_YET, error)
        self, result: dict[str, Any], on_done: Callable[[str, str], None]
    ) -> None: ...
    def now(self) -> str: ...
    def epoch(self) -> float: ...  # seconds since the epoch, as the DSR's stamps
    def dsr_boot(self) -> str: ...
    def out_of_reach(self) -> frozenset[str]: ...  # agents the DSR server cannot hear now
    def reach_losses(self) -> int: ...  # how often an agent has gone out of its reach


class HighLevelExecutive:
    KIND = "barthel"  # the test this executive runs (the Start request's requested_test)
    CLOSING = CLOSING

    def __init__(
        self,
        port: Port,
        times: Times,
        log,
        definition: Definition | None = None,
        place: tuple[str, ...] = orientation.DEFAULT_PLACE,
    ):
        self.port = port
        self.times = times
        self.log = log
        # the test as its file says it (by default this executive's KIND's); filled with today's
        # date and the place when it runs
        if definition is None and self.KIND in definitions.tests():
            definition = definitions.load(self.KIND)
        self.template = self.definition = definition
        if definition is not None:
            self.KIND = definition.test
        self.place = tuple(place)
        self.graph: Graph | None = None
        self.running = False
        self.record: QuestionnaireRecord | None = None
        self.state: frozenset[str] = frozenset()
        self.plan: list[Step] = []
        self.current: Step | None = None
        self._token = 0  # identifies the step in progress; stale callbacks compare it
        self._wait: Wait | None = None  # what the current step waits for in the graph
        self._timer: Timer | None = None
        self._pending_say: sentences.Sentence | None = None
        self._untaken_warned = False  # said once per sentence that no agent took it
        self._sentence_cut = False  # the sentence in progress waited for agents out of reach
        self._say_in_flight = False
        self._stuck = False  # the planner found no plan: do not resume that test again
        # Start requests already taken or refused, as (patient, when pressed): the replica shows
        # a request until the server's answer to our transaction comes back
        self._handled: set[tuple[str, Any]] = set()

    # ------------------------------------------------------------------ inputs
    def start(self, graph: Graph, patient: str) -> bool:
        """The clinician pressed Start. False if a test is already running."""
        if self.running:
            self.log.warning(
                f"a test is already running (patient {self.record.patient}); start ignored"
            )
            return False
        self.graph = graph
        self.running = True
        self._stuck = False
        self.definition = self._today()
        self.record = QuestionnaireRecord(self.definition, patient, self.port.now())
        self.state = decision_support.initial_state(
            low_to_high.person_present(graph), self.definition
        )
        self.port.event(event="started", patient=patient, test=self.KIND)
        self.port.send(high_to_low.start_test(graph, patient, self.record.started, self.definition))
        self._replan("start")
        return True

    def resume(self, graph: Graph) -> None:
        """A test is running in the DSR and this executive was not running it (it restarted):
        go on from what the DSR says, asking the item in progress again."""
        self.graph = graph
        self.running = True
        self.definition = self._today()
        self.record = low_to_high.record(graph, self.definition)
        self.state = low_to_high.facts(graph, self.definition)
        reset = high_to_low.reset_answer(graph)
        if reset is not None:  # a window left open by the previous run: it is asked again
            self.port.send(reset)
            item = graph.node("test").attrs.get("item")
            if item in self.record.items and not self.record.items[item].closed:
                self._window_ended(item, "interrupted")
        self.port.event(
            event="resumed", patient=self.record.patient, item=graph.node("test").attrs.get("item")
        )
        self._replan("resumed after a restart")

    def on_graph(self, graph: Graph) -> None:
        """The replica changed (or was reloaded)."""
        self.graph = graph
        requested = low_to_high.start_request(graph)
        request = (requested, graph.node("test").attrs.get("requested"))
        if requested is not None and request in self._handled:
            requested = None
        if not self.running:
            # one executive per test: each takes the Starts of its own test, and the one running
            # a test refuses every other Start
            running = low_to_high.test_running(graph)
            ours = low_to_high.running_test(graph) == self.KIND
            if running and ours and not self._stuck:
                self.resume(graph)
            elif (
                requested is not None
                and low_to_high.requested_test(graph) == self.KIND
                and not (running and not ours)
            ):
                self._handled.add(request)
                self.start(graph, requested)
            return
        if requested is not None:
            self._handled.add(request)
            self.log.warning(f"Start for {requested} while a test runs: refused")
            self.port.send(high_to_low.refuse_start(graph, requested))
        self._watch_person(graph)
        if (
            self._pending_say is not None
            and not self._say_in_flight
            and low_to_high.channels_idle(graph)
        ):
            self._write_sentence()
        self._check_wait(graph)

    # ------------------------------------------------------------------ planning and stepping
    def _replan(self, reason: str) -> None:
        self._cancel_step()
        try:
            self.plan = self._plan(self.state)
        except decision_support.NoPlan as e:
            self.log.error(str(e))
            self.port.event(event="error", message=str(e))
            self.running = False
            self._stuck = True
            return
        self.port.event(
            event="plan",
            reason=reason,
            steps=len(self.plan),
            first=str(self.plan[0]) if self.plan else "",
        )
        self._next()

    def _today(self) -> Definition:
        """The test's definition with orientation filled in: today's date (the robot's local
        time) and the place."""
        today = datetime.fromtimestamp(self.port.epoch()).date()
        return self.template.filled(orientation.values(today, self.place))

    def _plan(self, state: frozenset[str]) -> list[Step]:
        return decision_support.plan(state, self.definition)

    def _person_lost_state(self) -> frozenset[str]:
        """The facts after the person left in the middle of the plan."""
        return monitoring.person_lost(self.state, self._current_item())

    def _next(self) -> None:
        if not self.plan:
            self.running = False
            return
        step = self.plan.pop(0)
        self.current = step
        self._token += 1
        self.port.event(event="step", step=str(step))
        handler = self.ACTIONS.get(step.name)
        if handler is None:  # a domain with an action this executive cannot carry out
            self.log.error(f"no handler for the plan's action {step}")
            self.port.event(event="error", message=f"PELEA cannot carry out {step}")
            self.running = False
            return
        handler(self, step, *step.args)

    def _complete(self, token: int, state: frozenset[str] | None = None) -> None:
        """The step with ``token`` ended: as planned (``state`` None) or with a deviation."""
        if token != self._token or self.current is None:
            return  # a step already abandoned
        step, self.current = self.current, None
        self._clear_wait()
        if state is None:
            self.state = step.apply(self.state)
            if step.name in PROGRESS_FLAGS:  # so that a restarted executive does not redo it
                self.port.send(high_to_low.record_test(**{PROGRESS_FLAGS[step.name]: True}))
            if self._monitor():
                self._replan("two items unanswered: call the clinician")
            else:
                self._next()
        else:
            self.state = state
            self._replan(f"deviation in {step}")

    def _monitor(self) -> bool:
        """Deviations visible only at the high level: two unanswered items need the clinician."""
        if (
            not self.record.clinician_called
            and len(self.record.unanswered) >= 2
            and "(clinician-ok)" in self.state
        ):
            self.state = monitoring.clinician_needed(self.state)
            return True
        return False

    def _cancel_step(self) -> None:
        self._token += 1
        self.current = None
        self._clear_wait()
        self._pending_say = None

    def _clear_wait(self) -> None:
        self._wait = None
        if self._timer is not None:
            self._timer.cancel()
            self._timer = None

    # ------------------------------------------------------------------ waiting on the graph
    def _check_wait(self, graph: Graph) -> None:
        wait = self._wait
        if isinstance(wait, SentenceWait) and low_to_high.sentence_done(graph, wait.sid):
            self._complete(wait.token)
        elif isinstance(wait, PersonWait) and low_to_high.person_present(graph):
            self.port.event(event="person_back")
            self._complete(wait.token)
        elif isinstance(wait, AnswerWait):
            self._on_answer(graph, wait)

    def _watch_person(self, graph: Graph) -> None:
        present = low_to_high.person_present(graph)
        if "(person-present)" in self.state and not present:
            self.record.person_lost_count += 1
            self.port.send(high_to_low.record_test(person_lost_count=self.record.person_lost_count))
            self.port.event(event="person_lost")
            if self.current is not None and self.current.name in self.CLOSING:
                self.state = (self.state - {"(person-present)"}) | {"(person-absent)"}
                return
            if isinstance(self._wait, AnswerWait):
                close = high_to_low.close_answer(graph)
                if close is not None:
                    self.port.send(close)
            self.state = self._person_lost_state()
            self._replan("the person left")
        elif "(person-absent)" in self.state and present:
            if self.current is not None and self.current.name in ("ask-to-sit", "wait-for-person"):
                return  # the plan is already about it: wait-for-person completes
            self.port.event(event="person_back")
            self.state = monitoring.person_back(self.state)
            self._replan("the person is back")

    def _current_item(self) -> str:
        return next(
            (f[len("(current ") : -1] for f in self.state if f.startswith("(current ")),
            self.definition.order[0],
        )

    # ------------------------------------------------------------------ sentences
    def _say(self, sentence: sentences.Sentence) -> None:
        self._pending_say = sentence
        self.port.event(event="say", text=sentence.text, item=sentence.item)
        if low_to_high.channels_idle(self.graph):
            self._write_sentence()

    def _write_sentence(self) -> None:
        sentence, token = self._pending_say, self._token
        sid = low_to_high.last_sentence_id(self.graph) + 1
        self._say_in_flight = True

        def written(result) -> None:
            self._say_in_flight = False
            if token != self._token:
                return
            if not result.accepted:  # Speech or Panel still busy: retry on the next change
                self.log.debug(f"sentence not written yet: {result.error}")
                if self.graph is not None and low_to_high.channels_idle(self.graph):
                    self._write_sentence()
                return
            self._pending_say = None
            self._untaken_warned = False
            self._sentence_cut = False
            self._wait = SentenceWait(sid, token)
            self._timer = self.port.after(
                self.times.sentence_timeout(sentence.text),
                lambda: self._sentence_timed_out(token, sentence.text),
            )
            self._check_wait(self.graph)

        self.port.send(high_to_low.say(self.graph, sentence, sid), written)

    def _sentence_timed_out(self, token: int, text: str) -> None:
        if token != self._token:
            return
        wait = self._wait
        away = self.port.out_of_reach()
        if isinstance(wait, SentenceWait) and (away or self._sentence_cut):
            # Cut off while saying it: its end is held on the other side of the link, and
            # arrives when the link is back.
            if away and not self._sentence_cut:
                self.log.warning(f"{', '.join(sorted(away))} out of reach: waiting for {text!r}")
            self._sentence_cut = bool(away)
            self._timer = self.port.after(
                REACH_RECHECK if away else CUT_SETTLE,
                lambda: self._sentence_timed_out(token, text),
            )
            return
        if isinstance(wait, SentenceWait) and not low_to_high.sentence_taken(self.graph, wait.sid):
            # Neither Speech nor Panel even started it: they are out of reach (a network cut,
            # both restarting), and the patient heard nothing. Going on would ask for an answer
            # to an unheard question: wait for them instead (the sentence is in the DSR).
            if not self._untaken_warned:
                self._untaken_warned = True
                self.log.warning(f"no agent took {text!r}: waiting for Speech and Panel")
                self.port.event(event="warning", message=f"no agent took the sentence: {text}")
            self._timer = self.port.after(
                self.times.sentence_timeout(text), lambda: self._sentence_timed_out(token, text)
            )
            return
        self.log.warning(f"no agent finished saying/showing {text!r} in time; going on")
        self.port.event(event="warning", message=f"sentence not finished in time: {text}")
        self._complete(token)

    # ------------------------------------------------------------------ the actions of the plan
    def _ask_to_sit(self, step: Step) -> None:
        self._say(sentences.sit_down())

    def _wait_for_person(self, step: Step) -> None:
        self._wait = PersonWait(self._token)
        self._check_wait(self.graph)

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

    def _await_answer_again(self, step: Step, item: str) -> None:
        self._open_window(item, 2)

    def _open_window(self, item: str, window: int) -> None:
        token = self._token
        result = self.record.items[item]
        result.attempts += 1
        self.port.send(high_to_low.record_item(result))
        self.port.event(event="listening", item=item, window=window)

        def opened(r) -> None:
            if token != self._token:
                return
            if not r.accepted:  # the person left at this very moment: _watch_person replans
                self.log.info(f"could not open the answer window: {r.error}")
                return
            wait = AnswerWait(item, window, token, self.port.dsr_boot(), self.port.reach_losses())
            self._wait = wait
            self._timer = self.port.after(
                self.times(self.times.answer_timeout), lambda: self._answer_timed_out(wait)
            )
            self._check_wait(self.graph)

        self.port.send(high_to_low.open_answer(self.graph, item), opened)

    def _on_answer(self, graph: Graph, wait: AnswerWait) -> None:
        item, window, token = wait.item, wait.window, wait.token
        answer = low_to_high.answer(graph)
        if answer is None:
            return
        self.port.send(high_to_low.consume_answer())
        if answer.item != item:
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

    def _window_ended(self, item: str, outcome: str, heard: str = "") -> None:
        """Written to the item's node: how its window ended, for observers and for a restart."""
        result = self.record.items[item]
        result.outcomes.append(outcome)
        if heard:
            result.heard = heard
        self.port.send(high_to_low.record_item(result))

    def _answer_timed_out(self, wait: AnswerWait, over: Overtime | None = None) -> None:
        item, window, token = wait.item, wait.window, wait.token
        over = over or Overtime()
        if token != self._token or self.graph is None:
            return
        close = high_to_low.close_answer(self.graph)
        if close is None:
            return  # the answer is already there; _check_wait takes it

        def later(seconds: float) -> None:
            self._timer = self.port.after(seconds, lambda: self._answer_timed_out(wait, over))

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
            # A DSR server that restarted during the window may have lost an answer given then:
            # Speech sends it again, but the close may reach the new server first. Such a
            # window is asked again, never counted as silence.
            if interrupted or self.port.dsr_boot() != wait.boot:
                self._window_ended(item, "interrupted")
                self.port.event(event="window_interrupted", item=item, window=window)
                self._complete(token, monitoring.window_interrupted(self.state, item, window))
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

    def _skip_item(self, step: Step, item: str) -> None:
        self.record.give_up(item)
        self.port.send(high_to_low.record_item(self.record.items[item]))
        self.port.event(event="unanswered", item=item)
        self._complete(self._token)

    def _next_item(self, step: Step, item: str, following: str) -> None:
        self.port.send(high_to_low.current_item(following))
        self._complete(self._token)

    def _call_clinician(self, step: Step) -> None:
        self.record.clinician_called = True
        unanswered = ", ".join(self.record.unanswered)
        self.port.notify_clinician(
            f"{self.record.patient} left {len(self.record.unanswered)} questions unanswered "
            f"({unanswered}) in the {self.definition.title}: please come and attend."
        )
        self.port.event(event="clinician_called", unanswered=self.record.unanswered)
        self.port.send(high_to_low.call_clinician(self.graph))
        self._say(sentences.call_clinician())

    def _say_goodbye(self, step: Step, item: str) -> None:
        self._say(sentences.goodbye(self.definition, self.record.patient))

    def _set_timer(self, timer: Timer) -> None:
        self._timer = timer

    def _store_result(self, step: Step) -> None:
        """The result, as the DSR holds it, to CGAmed (which stores a test once, however often
        it is sent); the test is finished in the DSR once CGAmed acknowledged it."""
        token = self._token
        finished = self.graph.node("test").attrs.get("finished") or self.port.now()

        def written(r) -> None:
            if token != self._token:
                return
            if not r.accepted:
                self.log.warning(f"could not record the end of the test: {r.error}; retrying")
                self._timer = self.port.after(
                    self.times.store_retry, lambda: self._store_result(step)
                )
                return
            result = low_to_high.record(self.graph, self.definition).to_json()
            self.record.finished = finished
            deliver(
                self.port,
                result,
                self.times.store_retry,
                self.log,
                lambda: token == self._token,
                lambda outcome: ended(result, outcome),
                self._set_timer,
            )

        def ended(result: dict[str, Any], outcome: str) -> None:
            self.port.send(high_to_low.finish_test(self.graph))
            self.port.event(event="finished" if outcome == STORED else "refused", result=result)
            self._complete(token)

        self.port.send(high_to_low.record_test(finished=finished), written)

    # The plan's actions, each with its handler; a test checks it against the PDDL domain.
    ACTIONS: dict[str, Callable[..., None]] = {
        "ask-to-sit": _ask_to_sit,
        "wait-for-person": _wait_for_person,
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
        "skip-item": _skip_item,
        "next-item": _next_item,
        "call-clinician": _call_clinician,
        "say-goodbye": _say_goodbye,
        "store-result": _store_result,
    }
