"""PELEA as a ROS node: the High Level Executive connected to the DSR, the CGAmed start command,
the clinician's notifications and the results store.

ROS Parameters:
    time_scale (float): multiplies every time of the flow (default 1.0: a real session).
    answer_timeout (float): seconds of a real session an answer window stays open (default 8).
    outbox_dir (str): results not yet acknowledged by CGAmed wait here, so a crash loses none
        (default $XDG_STATE_HOME/clarc/pelea_outbox).
    setup_timeout (float): seconds to wait for the DSR server (default 20).
    place (string[]): where the robot is, as orientation is scored: country, province, city,
        building, floor ("|" between the ways of saying one; default the paper's hospital).
Tests: every questionnaire in clarc_agents/definitions (barthel, lawton, mmse) and the Get Up
& Go; one executive each.
Start: a request on the DSR's test node (clarc start, or the dashboard).
Publishers: clarc/pelea/events, clarc/cgamed/notify.
Clients: clarc/cgamed/store_result (dsr_msgs/srv/StoreResult). Plus the DSR topics.
"""

from __future__ import annotations

import json
import time
from collections.abc import Callable
from datetime import UTC, datetime
from pathlib import Path
from typing import Any

from std_msgs.msg import String

from clarc_agents import definitions, test_node, topics
from clarc_agents.pelea.gug_executive import GugExecutive
from clarc_agents.pelea.questionnaire_executive import QuestionnaireExecutive, QuestionnaireTimes
from clarc_agents.pelea.result_delivery import NOT_YET, REFUSED, STORED
from clarc_agents.questionnaire.orientation import DEFAULT_PLACE, place_values
from dsr_graph.formats.default_paths import state_path
from dsr_graph.formats.private_files import private_dir
from dsr_graph.formats.safe_json import loads_object
from dsr_graph.formats.world_files import write_json_atomically
from dsr_graph.ros.agent import DsrAgent
from dsr_graph.ros.dsr_node import DsrNode, main_for
from dsr_graph.ros.json_topics import publish_json
from dsr_graph.ros.parameters import (
    declare,
    declare_setup_timeout,
    declare_time_scale,
    float_param,
    param,
)
from dsr_graph.ros.qos import qos_stream
from dsr_graph.ros.timers import OneShot
from dsr_msgs.srv import StoreResult

STORE_TIMEOUT = 5.0  # seconds CGAmed may take to acknowledge a result


class PeleaNode(DsrNode):
    NAME = "pelea"

    @classmethod
    def declare_node_parameters(cls, node) -> None:
        declare_time_scale(node, "multiplies every time of the flow")
        declare(
            node,
            "answer_timeout",
            8.0,
            "seconds of a real session an answer window stays open",
            read_only=True,
            minimum=0.0,
        )
        declare(
            node,
            "outbox_dir",
            state_path("clarc", "pelea_outbox"),
            "results CGAmed has not acknowledged wait here",
            read_only=True,
        )
        declare_setup_timeout(node, 20.0)
        declare(
            node,
            "place",
            list(DEFAULT_PLACE),
            "country, province, city, building, floor: orientation is scored against them",
            read_only=True,
        )

    def __init__(self):
        super().__init__()
        self.dsr = DsrAgent()
        times = QuestionnaireTimes(
            scale=float_param(self, "time_scale"),
            answer_timeout=float_param(self, "answer_timeout"),
        )
        place = tuple(param(self, "place"))
        place_values(place)  # a wrong place ends the node now, naming what is wrong
        self.executives = [
            QuestionnaireExecutive(self, times, self.get_logger(), definitions.load(test), place)
            for test in definitions.tests()
        ]
        self.executives.append(GugExecutive(self, times, self.get_logger()))
        self._refused: set[tuple[str, Any]] = set()  # Starts for a test no executive runs
        self.outbox = Path(param(self, "outbox_dir"))

    def setup(self) -> None:
        private_dir(self.outbox)
        self._events = self.create_publisher(String, topics.PELEA_EVENTS, qos_stream())
        self._notify = self.create_publisher(String, topics.CGAMED_NOTIFY, qos_stream())
        self._store = self.create_client(StoreResult, topics.CGAMED_STORE)
        self.dsr.describe(can_do=["run a test"])
        self.dsr.setup(self, timeout_sec=float_param(self, "setup_timeout"))
        self.dsr.add_listener(self._on_graph)
        self.create_timer(2.0, self._flush_outbox)
        self.get_logger().info("PELEA up: waiting for the clinician's Start")

    def _on_graph(self, deltas, resynced) -> None:
        # A Start request, a test to resume after a restart, and the test's course: all in the DSR.
        # Each executive takes the Starts of its own test; the one running refuses the others.
        self._refuse_unknown_test()
        for executive in self.executives:
            executive.on_graph(self.dsr.graph)

    def _refuse_unknown_test(self) -> None:
        """A Start for a test none of the executives runs is dropped, saying so, rather than
        left waiting for an executive that will never come."""
        graph = self.dsr.graph
        patient = test_node.start_request(graph)
        if patient is None:
            return
        test, code = test_node.requested_test(graph), test_node.requested_language(graph)
        request = (patient, graph.node("test").attrs.get("requested"))
        runs = next((e for e in self.executives if e.KIND == test), None)
        if (runs is not None and code in runs.languages) or request in self._refused:
            return
        self._refused.add(request)
        if runs is None:
            kinds = ", ".join(e.KIND for e in self.executives)
            why = f"no test {test!r} here ({kinds})"
            message = f"unknown test {test!r}: Start refused"
        else:
            why = f"{test} is not shipped in {code!r} ({', '.join(runs.languages)})"
            message = f"{test} in {code!r}: no such language, Start refused"
        self.get_logger().error(f"Start for {patient}: {why}; refused")
        self.event(event="error", message=message)
        self.dsr.send(test_node.refuse_start(graph, patient))

    # ------------------------------------------------------------------ the HLE's port
    def send(self, tx: dict[str, Any], on_done=None) -> None:
        self.dsr.send(tx, on_done)

    def after(self, seconds: float, callback: Callable[[], None]) -> OneShot:
        return OneShot(self, seconds, callback)

    def event(self, **fields: Any) -> None:
        publish_json(self._events, fields)

    def notify_clinician(self, message: str) -> None:
        publish_json(self._notify, {"message": message})

    def dsr_boot(self) -> str:
        return self.dsr.boot

    def out_of_reach(self) -> frozenset[str]:
        return self.dsr.out_of_reach

    def reach_losses(self) -> int:
        return self.dsr.reach_losses

    def epoch(self) -> float:
        return time.time()

    def now(self) -> str:
        return datetime.now(UTC).isoformat(timespec="milliseconds")

    def store_result(self, result: dict[str, Any], on_done: Callable[[str, str], None]) -> None:
        # Kept on disk until CGAmed acknowledges it: a crash of PELEA or CGAmed loses nothing.
        path = self.outbox / f"{result['patient']}-{result['started']}.json".replace(
            ":", ""
        ).replace("/", "_")
        write_json_atomically(result, path)
        self._send_stored(path, result, on_done)

    def _send_stored(
        self, path: Path, result: dict[str, Any], on_done: Callable[[str, str], None]
    ) -> None:
        if not self._store.service_is_ready():
            on_done(NOT_YET, "the CGAmed results service is not available")
            return
        future = self._store.call_async(StoreResult.Request(result_json=json.dumps(result)))
        # An unanswered call (CGAmed restarting) is withdrawn and reported, so the HLE retries.
        watchdog = OneShot(
            self,
            STORE_TIMEOUT,
            lambda: (
                self._store.remove_pending_request(future),
                on_done(NOT_YET, f"no answer within {STORE_TIMEOUT} s"),
            ),
        )

        def answered(f) -> None:
            watchdog.cancel()
            if f.cancelled():
                return
            try:
                response = f.result()
            except Exception as e:  # noqa: BLE001 - any failure means: not stored, try again
                on_done(NOT_YET, repr(e))
                return
            if response.stored:
                path.unlink(missing_ok=True)
                self.get_logger().info(f"result stored in CGAmed as test {response.test_id}")
                on_done(STORED, "")
                return
            # CGAmed read it and refused it: sending it again would be refused again. Kept
            # aside (never lost), out of the outbox that is sent again at every start.
            refused = self.outbox / "refused" / path.name
            private_dir(refused.parent)
            if path.exists():
                path.replace(refused)
            on_done(REFUSED, response.error)

        future.add_done_callback(answered)

    def _flush_outbox(self) -> None:
        """Results left by an earlier run (crash before CGAmed answered) are sent again; one
        CGAmed refuses is moved to refused/ and the clinician told, once."""
        if any(executive.running for executive in self.executives):
            return
        for path in sorted(self.outbox.glob("*.json")):
            try:
                result = loads_object(path.read_bytes(), None)
            except (OSError, ValueError) as e:
                self.get_logger().error(f"unreadable result in the outbox {path}: {e}")
                continue
            self._send_stored(
                path, result, lambda outcome, error, r=result: self._leftover(r, outcome, error)
            )

    def _leftover(self, result: dict[str, Any], outcome: str, error: str) -> None:
        if outcome == REFUSED:
            self.notify_clinician(
                f"CGAmed refused the result of {result.get('patient')!r} started "
                f"{result.get('started')}: {error}. It is kept in PELEA's outbox (refused/)."
            )


main = main_for(PeleaNode)
