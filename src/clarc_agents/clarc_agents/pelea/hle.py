"""PELEA's High Level Executive (paper, Section III-B): the loop every test shares.

Loop: plan from the current state (Decision Support) -> execute the first action (HighToLow)
-> watch the DSR (LowToHigh) -> on completion apply the action's effects and go on; on a
deviation record it as facts (Monitoring) and plan again from there.

Crash-only: Start arrives as a request in the DSR, and everything needed to go on is written to
the DSR as the test runs; an executive that finds its test running there (it was restarted)
rebuilds its state from it and replans. The stored result is read from the DSR, never from
memory alone. Pure logic behind a small ``Port`` (send a transaction, start a timer, report,
store the result), so the whole course of a test can be driven by unit tests with a local
graph; ``nodes/pelea_node.py`` connects it to ROS.

What the core does for every test: take the Starts of its kind (and refuse others while one
runs), resume after a restart, plan and step, wait for the DSR (a sentence said and shown, the
person back) with timers, notice the person leaving and coming back, say sentences, call the
clinician, and deliver the result to CGAmed. A test is a subclass that says what is its own:
how it begins and is rebuilt from the DSR (``_begin``, ``_restore``), how it plans
(``_plan``), what the person leaving means (``_person_lost_state``), what else it waits for
(``_check_test_wait``), its result (``_result``) and its plan's actions (``ACTIONS``).
``questionnaire_executive`` runs every test a definition file describes (Barthel, MMSE,
Lawton); ``gug_executive`` the Get Up & Go.
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any, ClassVar, Protocol

from clarc_agents import test_node
from clarc_agents.pelea import decision_support, high_to_low, low_to_high, monitoring
from clarc_agents.pelea.decision_support import Step
from clarc_agents.pelea.result_delivery import STORED, deliver
from clarc_agents.sentence import Sentence
from dsr_graph.model.agent_info import missing_abilities
from dsr_graph.model.graph import Graph


@dataclass
class Times:
    """Every time of the flow, in seconds of a real session; ``scale`` shrinks them together."""

    scale: float = 1.0
    words_per_second: float = 2.5  # to bound how long a sentence may take
    sentence_slack: float = 5.0
    store_retry: float = 2.0
    agents_patience: float = 30.0  # waiting for a needed agent before the clinician is told

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
class AgentsWait:
    """Every agent the test needs is ready (model/agent_info.py): the step waits to begin."""

    token: int


@dataclass(frozen=True)
class PersonWait:
    """The person is in front of the robot again."""

    token: int


REACH_RECHECK = 0.5  # seconds between looks at whether agents out of reach are back
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


class HighLevelExecutive(ABC):
    KIND: str = ""  # the test this executive runs (the Start request's requested_test)
    languages: tuple[str, ...] = ("en",)  # what a Start may ask it in (requested_language)
    CLOSING: tuple[str, ...] = ()  # actions not broken off when the person leaves: it is over
    ACTIONS: ClassVar[dict[str, Callable[..., None]]] = {}  # the plan's actions, each a handler
    # what the test needs agents ready for (their can_do): no step begins without them, so the
    # robot never asks while nobody listens (a Speech still starting, restarting, gone)
    NEEDS: ClassVar[tuple[str, ...]] = ()
    # the steps whose completion is written on the test node, each with its flag there (the
    # other steps leave their own trace), so that a restarted executive does not redo them
    PROGRESS_FLAGS: ClassVar[dict[str, str]] = {}

    def __init__(self, port: Port, times: Times, log):
        self.port = port
        self.times = times
        self.log = log
        self.graph: Graph | None = None
        self.running = False
        self.record: Any = None  # the test's own record: patient, person_lost_count, finished
        self.state: frozenset[str] = frozenset()
        self.plan: list[Step] = []
        self.current: Step | None = None
        self._token = 0  # identifies the step in progress; stale callbacks compare it
        self._wait: Any = None  # what the current step waits for in the graph
        self._timer: Timer | None = None
        self._pending_say: Sentence | None = None
        self._untaken_warned = False  # said once per sentence that no agent took it
        self._sentence_cut = False  # the sentence in progress waited for agents out of reach
        self._say_in_flight = False
        self._stuck = False  # the planner found no plan: do not resume that test again
        # Start requests already taken or refused, as (patient, when pressed): the replica shows
        # a request until the server's answer to our transaction comes back
        self._handled: set[tuple[str, Any]] = set()

    # ------------------------------------------------------------------ what a test says
    @abstractmethod
    def _begin(self, graph: Graph, patient: str) -> dict[str, Any]:
        """A new test for ``patient``: set ``record`` and ``state``; the transaction that takes
        the Start request and writes the test in the DSR."""

    @abstractmethod
    def _restore(self, graph: Graph) -> dict[str, Any]:
        """The test running in the DSR, taken over after a restart: set ``record`` and
        ``state``; what the "resumed" event says of where it was."""

    @abstractmethod
    def _plan(self, state: frozenset[str]) -> list[Step]: ...

    @abstractmethod
    def _person_lost_state(self) -> frozenset[str]:
        """The facts after the person left in the middle of the plan (and what the step in
        progress held open in the DSR undone)."""

    @abstractmethod
    def _result(self) -> dict[str, Any]:
        """The result to store, as the DSR holds it."""

    @abstractmethod
    def _check_test_wait(self, graph: Graph, wait: Any) -> None:
        """The graph changed while the step waits for something of the test's own (not a
        sentence, not the person)."""

    def _monitor(self) -> str | None:
        """A deviation visible only at the high level: written in ``state``, and the reason to
        replan returned."""
        return None

    # ------------------------------------------------------------------ inputs
    def start(self, graph: Graph, patient: str) -> bool:
        """The clinician pressed Start. False if a test is already running."""
        if self.running:
            self.log.warning(
                f"a test is already running (patient {self.record.patient}); start ignored"
            )
            return False
        self.graph, self.running, self._stuck = graph, True, False
        tx = self._begin(graph, patient)
        self.port.event(event="started", patient=patient, test=self.KIND)
        self.port.send(tx)
        self._replan("start")
        return True

    def resume(self, graph: Graph) -> None:
        """A test of ours is running in the DSR and this executive was not running it (it
        restarted): go on from what the DSR says."""
        self.graph, self.running = graph, True
        where = self._restore(graph)
        self.port.event(event="resumed", patient=self.record.patient, test=self.KIND, **where)
        self._replan("resumed after a restart")

    def on_graph(self, graph: Graph) -> None:
        """The replica changed (or was reloaded)."""
        self.graph = graph
        requested = test_node.start_request(graph)
        request = (requested, graph.node("test").attrs.get("requested"))
        if requested is not None and request in self._handled:
            requested = None
        if not self.running:
            # one executive per test: each takes the Starts of its own test, and the one running
            # a test refuses every other Start
            running = test_node.test_running(graph)
            ours = test_node.running_test(graph) == self.KIND
            if running and ours and not self._stuck:
                self.resume(graph)
            elif (
                requested is not None
                and test_node.requested_test(graph) == self.KIND
                and test_node.requested_language(graph) in self.languages
                and not (running and not ours)
            ):
                self._handled.add(request)
                self.start(graph, requested)
            return
        if requested is not None:
            self._handled.add(request)
            self.log.warning(f"Start for {requested} while a test runs: refused")
            self.port.send(test_node.refuse_start(graph, requested))
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

    def _next(self) -> None:
        if not self.plan:
            self.running = False
            return
        closing = self.plan[0].name in self.CLOSING  # the result is stored whoever is gone
        missing = [] if closing or self.graph is None else self._agents_missing(self.graph)
        if missing:
            self._wait_for_agents(missing)
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
            if step.name in self.PROGRESS_FLAGS:
                self.port.send(test_node.record_test(**{self.PROGRESS_FLAGS[step.name]: True}))
            deviation = self._monitor()
            if deviation:
                self._replan(deviation)
            else:
                self._next()
        else:
            self.state = state
            self._replan(f"deviation in {step}")

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

    def _set_timer(self, timer: Timer) -> None:
        self._timer = timer

    # ------------------------------------------------------------------ waiting on the graph
    def _agents_missing(self, graph: Graph) -> list[str]:
        return missing_abilities(graph, self.NEEDS, away=self.port.out_of_reach())

    def _wait_for_agents(self, missing: list[str]) -> None:
        """The next step waits until agents that can do ``missing`` are ready (looked at on
        every change of the graph, and every REACH_RECHECK for the server's reach); the
        clinician is told if that takes longer than ``agents_patience``."""
        self._token += 1
        token = self._token
        self._wait = AgentsWait(token)
        self.log.warning(f"waiting for an agent ready to {', '.join(missing)} before going on")
        self.port.event(event="waiting_for_agents", missing=missing)
        self._recheck_agents(token, waited=0.0, told=False)

    def _recheck_agents(self, token: int, waited: float, told: bool) -> None:
        if token != self._token or not isinstance(self._wait, AgentsWait):
            return
        self._check_wait(self.graph)
        if token != self._token or not isinstance(self._wait, AgentsWait):
            return  # they are ready: the step began
        if not told and waited >= self.times(self.times.agents_patience):
            still = self._agents_missing(self.graph)
            self.port.notify_clinician(
                f"The robot is waiting to go on with the {self.KIND} test: nothing is ready to "
                f"{', '.join(still)} (an agent is starting, restarting or gone). Please check it."
            )
            self.port.event(event="agents_missing", missing=still)
            told = True
        self._timer = self.port.after(
            REACH_RECHECK, lambda: self._recheck_agents(token, waited + REACH_RECHECK, told)
        )

    def _check_wait(self, graph: Graph) -> None:
        wait = self._wait
        if isinstance(wait, AgentsWait):
            if not self._agents_missing(graph):
                self._clear_wait()
                self.port.event(event="agents_ready")
                self._next()
        elif isinstance(wait, SentenceWait):
            if low_to_high.sentence_done(graph, wait.sid):
                self._complete(wait.token)
        elif isinstance(wait, PersonWait):
            if test_node.person_present(graph):
                self.port.event(event="person_back")
                self._complete(wait.token)
        elif wait is not None:
            self._check_test_wait(graph, wait)

    def _watch_person(self, graph: Graph) -> None:
        present = test_node.person_present(graph)
        if "(person-present)" in self.state and not present:
            self.record.person_lost_count += 1
            self.port.send(test_node.record_test(person_lost_count=self.record.person_lost_count))
            self.port.event(event="person_lost")
            if self.current is not None and self.current.name in self.CLOSING:
                self.state = (self.state - {"(person-present)"}) | {"(person-absent)"}
                return
            self.state = self._person_lost_state()
            self._replan("the person left")
        elif "(person-absent)" in self.state and present:
            if self.current is not None and self.current.name in ("ask-to-sit", "wait-for-person"):
                return  # the plan is already about it: wait-for-person completes
            self.port.event(event="person_back")
            self.state = monitoring.person_back(self.state)
            self._replan("the person is back")

    # ------------------------------------------------------------------ sentences
    def _say(self, sentence: Sentence) -> None:
        """Say (and show) ``sentence``; the step completes when Speech and Panel are done."""
        self._pending_say = sentence
        self.port.event(event="say", text=sentence.text, item=sentence.item)
        if low_to_high.channels_idle(self.graph):
            self._write_sentence()
        else:
            token = self._token
            self.port.after(
                self.times(self.times.agents_patience), lambda: self._still_busy(token, sentence)
            )

    def _still_busy(self, token: int, sentence: Sentence) -> None:
        """A sentence has waited ``agents_patience`` for Speech or Panel to end their last
        action (a channel an agent never freed): the clinician is told, once; the sentence is
        said when the channel is free."""
        if token != self._token or self._pending_say is not sentence or self.graph is None:
            return
        busy = low_to_high.busy_channels(self.graph)
        if not busy:
            return
        self.log.warning(
            f"waiting for the robot to end its {' and '.join(busy)} to say {sentence.text!r}"
        )
        self.port.event(event="channels_busy", busy=busy)
        waited = self.times(self.times.agents_patience)
        self.port.notify_clinician(
            f"The robot is waiting to go on with the {self.KIND} test: it has not ended its "
            f"{' and '.join(busy)} for {waited:g} s. Please check it."
        )

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

    # ------------------------------------------------------------------ actions every test has
    def _wait_for_person(self, step: Step) -> None:
        self._wait = PersonWait(self._token)
        self._check_wait(self.graph)

    def _tell_clinician(self, message: str, unanswered: list[str]) -> None:
        """The clinician is called (CGAmed tells them ``message``) and the DSR says so."""
        self.record.clinician_called = True
        self.port.notify_clinician(message)
        self.port.event(event="clinician_called", unanswered=unanswered)
        self.port.send(test_node.call_clinician(self.graph))

    def _store_result(self, step: Step) -> None:
        """The result to CGAmed; the step completes once it is stored (or refused)."""
        token = self._token

        def ended(doc: dict[str, Any], outcome: str) -> None:
            self.port.event(event="finished" if outcome == STORED else "refused", result=doc)
            self._complete(token)

        self._deliver(token, ended)

    def _deliver(self, token: int, ended: Callable[[dict[str, Any], str], None]) -> None:
        """The result, as the DSR holds it, to CGAmed (which stores a test once, however often
        it is sent), after the test node says when the test finished; once CGAmed stored or
        refused it the test is finished in the DSR and ``ended(result, outcome)`` is called."""
        finished = self.graph.node("test").attrs.get("finished") or self.port.now()

        def written(r) -> None:
            if token != self._token:
                return
            if not r.accepted:
                self.log.warning(f"could not record the end of the test: {r.error}; retrying")
                retry = lambda: self._deliver(token, ended)  # noqa: E731
                self._timer = self.port.after(self.times.store_retry, retry)
                return
            self.record.finished = finished
            doc = self._result()

            def stored(outcome: str) -> None:
                self.port.send(test_node.finish_test(self.graph))
                ended(doc, outcome)

            deliver(
                self.port,
                doc,
                self.times.store_retry,
                self.log,
                lambda: token == self._token,
                stored,
                self._set_timer,
            )

        self.port.send(test_node.record_test(finished=finished), written)
