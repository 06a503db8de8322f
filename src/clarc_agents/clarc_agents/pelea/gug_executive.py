"""PELEA's executive for the Get Up & Go test (Timed Up and Go), on the loop every test shares
(``hle.py``: plan -> act -> watch the DSR -> replan on a deviation), with its own planning domain
(``data/gug_domain.pddl``).

It explains the test, says "go", and waits for the gait analyser's timed result in the DSR's
``gait`` node; it never sees the skeleton itself. The DSR holds everything a restarted PELEA
needs: the test node (patient, kind, progress flags) and the gait node (``trial``, ``status``:
idle, timing, timed or void, ``go_at``; and the analyser's ``phase``, ``tug_seconds``,
``phase_seconds``, ``band``, ``fall_risk``).

Deviations: the patient leaves during a trial (it is void: they are asked to sit again and the
trial is repeated), the analyser voids it (a hole in the frames, not seated at go, the line not
reached, no turn), no timed result comes in time (void too), the patient does not come back, or
no trial is left after ``MAX_TRIALS``: the clinician is called and the test is stored as
"unable to perform" with each void trial's reason (the test node's ``void_reasons``).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from clarc_agents import test_node
from clarc_agents.gug import sentences
from clarc_agents.gug.high_to_low import start_test, time_trial, void_trial
from clarc_agents.gug.phases import WITHIN
from clarc_agents.gug.planning import GOAL, initial_state, problem_pddl
from clarc_agents.gug.record import GugRecord, gait, result
from clarc_agents.gug.skeleton import latest_frame_time
from clarc_agents.pelea import decision_support, low_to_high
from clarc_agents.pelea.decision_support import Step
from clarc_agents.pelea.hle import HighLevelExecutive, PersonWait
from clarc_agents.sentence import Sentence
from dsr_graph.model.graph import Graph

MAX_TRIALS = 3
# s of a session PELEA waits for the analyser's verdict beyond its own limit (``WITHIN`` of the
# frames' time from go), then between looks while frames still come, late, on a busy machine:
# the trial is void when no frame came since the last look, or the frames passed the limit
# with no verdict (no analyser)
VERDICT_WAIT = 30.0
ABSENT_TIMEOUT = 60.0  # s of a session the patient may stay away before the clinician is called


@dataclass(frozen=True)
class GaitWait:
    """The gait analyser's timed result of trial ``trial``."""

    trial: int
    token: int


class GugExecutive(HighLevelExecutive):
    KIND = "get_up_and_go"
    CLOSING = ("store-result", "say-goodbye", "call-clinician", "end-untimed")
    NEEDS = ("speak", "track the person", "time a Get Up & Go")  # speech, person, gait_analyser
    PROGRESS_FLAGS = {"explain": "explained", "say-goodbye": "said_goodbye"}

    def __init__(self, port, times, log):
        super().__init__(port, times, log)
        self.record: GugRecord | None = None
        self.trials = 0
        self.void_reasons: list[str] = []  # why each void trial did not count (test node's)
        self._last_phase = ""  # the analyser's phase last told as an event

    # ------------------------------------------------------------------ the test's own part
    def _begin(self, graph: Graph, patient: str) -> dict[str, Any]:
        self.trials, self.void_reasons = 0, []
        self.record = GugRecord(patient, self.port.now())
        self.state = initial_state(test_node.person_present(graph))
        return start_test(graph, patient, self.record.started)

    def _restore(self, graph: Graph) -> dict[str, Any]:
        """A trial being timed is waited for again."""
        t, g = graph.node("test").attrs, gait(graph)
        self.record = GugRecord(
            str(t.get("patient", "")),
            str(t.get("started", "")),
            int(t.get("person_lost_count", 0)),
            bool(t.get("clinician_called", False)),
        )
        self.trials = int(g.get("trial", 0))
        self.void_reasons = [str(r) for r in t.get("void_reasons", [])]
        facts = {"(started)"}
        facts.add("(person-present)" if test_node.person_present(graph) else "(person-absent)")
        if not t.get("explained"):
            facts.add("(unexplained)")
        status = g.get("status")
        if status == "timing":
            facts.add("(go-said)")
        elif status == "timed":
            facts.add("(trial-timed)")
        elif status == "void":
            facts.add("(trial-void)")
        elif t.get("explained"):  # explained, no trial yet: seat the patient and say go
            facts.add("(to-seat)")
        facts |= self._trials_facts()
        if self.record.clinician_called:
            facts = (facts - {"(trials-left)"}) | {"(trials-exhausted)", "(clinician-called)"}
        self.state = frozenset(facts)
        return {"trial": self.trials}

    def _plan(self, state: frozenset[str]) -> list[Step]:
        return decision_support.solve(
            decision_support.domain_path("gug"), problem_pddl(state), state, GOAL
        )

    def _result(self) -> dict[str, Any]:
        return result(self.graph, self.record)

    def _trials_facts(self) -> set[str]:
        return {"(trials-left)"} if self.trials < MAX_TRIALS else {"(trials-exhausted)"}

    def _void(self, state: frozenset[str], reason: str) -> frozenset[str]:
        """The trial in progress is abandoned (``reason``, kept for the result): another one,
        or none left."""
        if self.trials:
            self.port.send(void_trial(self.trials))
            self.void_reasons.append(f"trial {self.trials}: {reason}")
            self.port.send(test_node.record_test(void_reasons=list(self.void_reasons)))
        state = state - {"(go-said)", "(trials-left)", "(ready)", "(to-seat)"}
        facts = self._trials_facts()
        if "(trials-left)" in facts:
            facts.add("(trial-void)")
        self.port.event(event="trial_void", trial=self.trials, reason=reason)
        return frozenset(state | facts)

    def _person_lost_state(self) -> frozenset[str]:
        state = (self.state - {"(person-present)", "(sit-requested)"}) | {"(person-absent)"}
        if "(go-said)" in state or (self.current is not None and self.current.name == "say-go"):
            state = self._void(state, "the patient left during the trial")
        return state

    def _check_test_wait(self, graph: Graph, wait: Any) -> None:
        if not isinstance(wait, GaitWait):
            return
        g = gait(graph)
        if g.get("trial") != wait.trial:
            return
        if g.get("status") == "timed":
            self.port.event(
                event="timed",
                trial=wait.trial,
                tug_seconds=g.get("tug_seconds"),
                band=g.get("band"),
            )
            self._complete(wait.token)
        elif g.get("status") == "void":  # the analyser could not time it: try again at once
            reason = str(g.get("reason", "")) or "the gait analyser could not time it"
            self.log.warning(f"trial {wait.trial} is void: {reason}")
            self._complete(wait.token, self._void(self.state, reason))
        elif g.get("phase"):
            self._phase_seen(g["phase"])

    def _phase_seen(self, phase: str) -> None:
        if phase != self._last_phase:
            self._last_phase = phase
            self.port.event(event="phase", trial=self.trials, phase=phase)

    # ------------------------------------------------------------------ the plan's actions
    def _ask_to_sit(self, step: Step) -> None:
        self._say(Sentence(sentences.SIT, needs_person=False))

    def _wait_for_person(self, step: Step) -> None:
        token = self._token
        self._wait = PersonWait(token)
        self._timer = self.port.after(self.times(ABSENT_TIMEOUT), lambda: self._stayed_away(token))
        self._check_wait(self.graph)

    def _stayed_away(self, token: int) -> None:
        if token != self._token:
            return
        self.log.warning("the patient did not come back: calling the clinician")
        self.void_reasons.append("the patient did not come back")
        self.port.send(test_node.record_test(void_reasons=list(self.void_reasons)))
        self.trials = MAX_TRIALS
        state = self.state - {"(trials-left)", "(trial-void)", "(sit-requested)"}
        self._complete(token, frozenset(state | {"(trials-exhausted)"}))

    def _explain(self, step: Step) -> None:
        self._say(Sentence(sentences.EXPLAIN))

    def _repeat_trial(self, step: Step) -> None:
        self._say(Sentence(sentences.AGAIN))

    def _seat_patient(self, step: Step) -> None:
        self._say(Sentence(sentences.SIT))

    def _say_go(self, step: Step) -> None:
        self._say(Sentence(sentences.GO))

    def _await_result(self, step: Step) -> None:
        """Go was just said: the trial is timed from when the speaker ended it, as Speech wrote
        (the patient starts then), else from now (the analyser counts from go_at)."""
        self.trials += 1
        token, trial = self._token, self.trials
        ended = low_to_high.speech_ended_at(self.graph, low_to_high.last_sentence_id(self.graph))
        self.port.send(time_trial(trial, ended if ended is not None else self.port.epoch()))
        self.port.event(event="trial", trial=trial)
        self._wait = GaitWait(trial, token)
        self._look_for_verdict(token, trial, latest_frame_time(self.graph), WITHIN + VERDICT_WAIT)

    def _look_for_verdict(self, token: int, trial: int, seen: float | None, wait: float) -> None:
        self._timer = self.port.after(
            self.times(wait), lambda: self._no_verdict(token, trial, seen)
        )

    def _no_verdict(self, token: int, trial: int, seen_before: float | None) -> None:
        """No verdict yet: waited for again while new frames come that the analyser may not have
        judged (the last look's were short of its limit: a busy machine, they come late), else
        the trial is void."""
        if token != self._token:
            return
        go = float(gait(self.graph).get("go_at") or self.port.epoch())
        seen = latest_frame_time(self.graph)
        if seen is None or (seen_before is not None and seen <= seen_before):
            after = max((seen or go) - go, 0.0) / self.times(1.0)
            reason = f"no frames of the patient after {after:.1f} s from go"
        elif seen_before is None or seen_before - go <= self.times(WITHIN):
            self.log.info(f"trial {trial}: its frames come late (a busy machine): waiting on")
            self._look_for_verdict(token, trial, seen, VERDICT_WAIT)
            return
        else:
            reason = f"the gait analyser gave no verdict on frames past its {WITHIN:g} s limit"
        self.log.warning(f"trial {trial} is void: {reason}")
        self._complete(token, self._void(self.state, reason))

    def _say_goodbye(self, step: Step) -> None:
        self._say(Sentence(sentences.DONE, needs_person=False))

    def _call_clinician(self, step: Step) -> None:
        trials = f"{self.trials} trial{'s' if self.trials != 1 else ''}"
        self._tell_clinician(
            f"{self.record.patient} could not be timed in the Get Up & Go test ({trials}): "
            "please come and attend.",
            [],
        )
        self._complete(self._token)

    def _end_untimed(self, step: Step) -> None:
        """No trial could be timed: stored as "unable to perform", with each trial's reason."""

        def ended(doc: dict[str, Any], outcome: str) -> None:
            self.port.event(event="finished_untimed", patient=self.record.patient, result=doc)
            self._say(Sentence(sentences.DONE, needs_person=False))

        self._deliver(self._token, ended)

    ACTIONS = {
        "ask-to-sit": _ask_to_sit,
        "wait-for-person": _wait_for_person,
        "explain": _explain,
        "repeat-trial": _repeat_trial,
        "seat-patient": _seat_patient,
        "say-go": _say_go,
        "await-result": _await_result,
        "store-result": HighLevelExecutive._store_result,
        "say-goodbye": _say_goodbye,
        "call-clinician": _call_clinician,
        "end-untimed": _end_untimed,
    }
