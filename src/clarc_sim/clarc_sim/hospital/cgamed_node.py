"""The CGAmed hospital-server stand-in: the clinician's Start, the results store, the
clinician's notifications, and the clinician's dashboard in the browser (dashboard_app.py).

The dashboard's Start is a request written on the DSR's test node (as ``clarc start`` does),
which PELEA takes: a Start is never lost to a module that is restarting. The dashboard follows
the test from the DSR (clarc_agents/course.py), so it stays right across a restart of PELEA or
of CGAmed; from PELEA's own stream it shows only PELEA's errors.

ROS Parameters: db (SQLite path, default $XDG_DATA_HOME/clarc/cgamed.sqlite), dashboard (true),
host (127.0.0.1), port (8081), setup_timeout (20 s), allowed_hosts (Host names the dashboard
serves besides the loopback ones, comma-separated), session_idle (seconds, 900).
Subscriptions: clarc/cgamed/notify, clarc/pelea/events, clarc/speaker/events. Publishers:
clarc/cgamed/notifications. Services: clarc/cgamed/store_result (dsr_msgs/srv/StoreResult).
Plus the DSR topics (it writes Start).
"""

from __future__ import annotations

import sqlite3
from datetime import UTC, datetime
from typing import Any

from std_msgs.msg import String

from clarc_agents import topics
from clarc_agents.asr.clips import default_folder
from clarc_agents.course import Course, band_words, test_name
from clarc_agents.test_node import request_start
from clarc_sim.exceptions import InvalidResult
from clarc_sim.hospital.dashboard_app import DEFAULT_IDLE, TestStatus, make_app, session_key
from clarc_sim.hospital.results_store import ResultsStore, default_db
from dsr_graph.formats.safe_json import loads_object
from dsr_graph.ros.agent import DsrAgent
from dsr_graph.ros.dsr_node import DsrNode, main_for
from dsr_graph.ros.json_topics import publish_json, subscribe_json
from dsr_graph.ros.parameters import (
    allowed_hosts_of,
    declare,
    declare_allowed_hosts,
    declare_setup_timeout,
    float_param,
    param,
)
from dsr_graph.ros.qos import qos_stream
from dsr_graph.ros.web_bridge import Bridge
from dsr_graph.web.events import Broadcaster
from dsr_msgs.srv import StoreResult


class CgamedStandIn(DsrNode):
    NAME = "cgamed"

    @classmethod
    def declare_node_parameters(cls, node) -> None:
        declare(
            node, "db", default_db(), "SQLite results store (empty: this default)", read_only=True
        )
        declare_setup_timeout(node, 20.0)
        declare(node, "dashboard", True, "serve the clinician's dashboard", read_only=True)
        declare(node, "host", "127.0.0.1", "dashboard address", read_only=True)
        declare(
            node,
            "port",
            8081,
            "dashboard port (0: any free port)",
            read_only=True,
            minimum=0,
            maximum=65535,
        )
        declare_allowed_hosts(node)
        declare(
            node,
            "clips_dir",
            "",
            "the robot's clips of what patients said, played on the dashboard "
            "(the asr node's clips_dir; empty: its default, $ROS_HOME/clarc/clips)",
            read_only=True,
        )
        declare(
            node,
            "session_idle",
            DEFAULT_IDLE,
            "seconds without a request before a dashboard session ends",
            read_only=True,
            minimum=10.0,
        )

    def __init__(self):
        super().__init__()
        self.status = TestStatus()
        self.events = Broadcaster()
        self.store: ResultsStore | None = None
        self.bridge: Bridge | None = None
        # (patient, test, record id): pressed on the dashboard, to be written to the DSR
        self._start_for: tuple[str, str, int | None] | None = None
        self.dsr = DsrAgent()
        self.course = Course()
        self._shown: dict[str, Any] | None = None

    def setup(self) -> None:
        self.db = param(self, "db") or default_db()  # empty (a launch's unset argument): default
        self.store = ResultsStore(self.db, shared=True)  # used by the ROS thread
        self.bridge = Bridge(self)
        self._notifications = self.create_publisher(
            String, topics.CGAMED_NOTIFICATIONS, qos_stream()
        )
        self.create_service(StoreResult, topics.CGAMED_STORE, self.on_store)
        subscribe_json(self, topics.CGAMED_NOTIFY, self.on_notify, qos_stream())
        subscribe_json(self, topics.PELEA_EVENTS, self.on_pelea, qos_stream())
        subscribe_json(self, topics.SPEAKER, self.on_speaker, qos_stream())
        self.dsr.setup(self, timeout_sec=float_param(self, "setup_timeout"))
        self.dsr.add_listener(self._on_graph)
        self.create_timer(0.1, self._send_start)
        self.get_logger().info(f"results store: {self.store.path}")

    def press_start(self, patient: str, test: str = "barthel", patient_id: int | None = None):
        """The clinician pressed Start (from the dashboard's thread, or at start-up)."""
        self._start_for = (patient, test, patient_id)

    def _send_start(self) -> None:  # ROS thread
        pressed = self._start_for
        if pressed is None or not self.dsr.ready:
            return
        self._start_for = None
        patient, test, patient_id = pressed
        requested = datetime.now(UTC).astimezone().isoformat(timespec="seconds")
        request = request_start(patient, requested, test, patient_id, self.dsr.graph)
        self.dsr.send(request, lambda r: self._start_sent(patient, r))

    def _start_sent(self, patient: str, result) -> None:
        if result.accepted:
            self.get_logger().info(f"Start pressed for {patient}")
        else:
            self.get_logger().error(f"Start for {patient} refused by the DSR: {result.error}")

    def _tell(self, kind: str, message: str, **extra) -> None:
        note = {"kind": kind, "message": message, **extra}
        publish_json(self._notifications, note)  # sent first: a crash may repeat it, never lose it
        self.store.notify(kind, message, extra.get("test_id"))
        self.bridge.to_web(self.events.publish, "notification", note)
        self.get_logger().info(f"to the clinician: {message}")

    def on_pelea(self, event: dict[str, Any]) -> None:
        if event.get("event") == "error":
            self.bridge.to_web(self.events.publish, "pelea", event)

    def _on_graph(self, deltas, resynced) -> None:  # ROS thread: the test from the DSR
        for step in self.course.follow(self.dsr.graph):
            self.bridge.to_web(self.events.publish, "step", step)
        status = TestStatus.of(self.course.current)
        if status != self._shown:
            self._shown = status
            self.bridge.to_web(self._show_status, status)

    def _show_status(self, status: dict[str, Any]) -> None:  # web thread
        self.status.update(status)
        self.events.publish("status", self.status.to_json())

    def on_speaker(self, event: dict[str, Any]) -> None:
        self.bridge.to_web(self.events.publish, "speaker", event)

    def on_store(self, request: StoreResult.Request, response: StoreResult.Response):
        try:
            result = loads_object(request.result_json)
            response.test_id = self.store.store(result)
            response.stored = True
        except (ValueError, InvalidResult) as e:  # nothing stored: each refusal named
            response.stored, response.error = False, f"result refused: {e}"
            self.get_logger().warning(f"refused a result on {topics.CGAMED_STORE}: {e}")
            return response
        except sqlite3.Error as e:  # the store itself failed: not stored, PELEA sends it again
            response.stored, response.error = False, f"the results store failed: {e}"
            self.get_logger().error(response.error)
            return response
        if self.store.notified("result_stored", response.test_id):
            return response  # the same test sent again (PELEA or CGAmed restarted): stored once
        if result.get("test") == "get_up_and_go" and result.get("tug_seconds") is None:
            score = f"{result['band']} after {result['trials']} trials, fall risk"  # unable
        elif result.get("test") == "get_up_and_go":
            score = f"{result['tug_seconds']:.1f} s, {result['band']}" + (
                ", fall risk" if result["fall_risk"] else ""
            )
        elif result.get("test", "barthel") == "barthel":
            score = f"{result['total']}/100, {band_words(result)}"
        else:
            score = f"{result['total']}/{result['max_total']}, {band_words(result)}"
            waiting = [i["item"] for i in result["items"] if i["needs_clinician"] and i["via"]]
            score += f"; please score {', '.join(waiting)}" if waiting else ""
        self._tell(
            "result_stored",
            f"The {test_name(result.get('test', 'barthel'))} of {result['patient']} is stored "
            f"(test {response.test_id}: {score}); please validate it.",
            test_id=response.test_id,
            result=result,
        )
        return response

    def on_notify(self, note: dict[str, Any]) -> None:
        self._tell("clinician_called", str(note["message"]))

    def run(self) -> int:
        if not param(self, "dashboard"):
            return super().run() or 0
        app = make_app(
            self.db,
            self.status,
            self.events,
            self.press_start,
            secret_key=session_key(self.db),
            hosts=allowed_hosts_of(self),
            idle=float_param(self, "session_idle"),
            clips_dir=str(param(self, "clips_dir")) or default_folder(),
        )
        served = self.bridge.serve(
            app,
            param(self, "host"),
            param(self, "port"),
            on_ready=lambda url: self.get_logger().info(f"clinician's dashboard on {url}"),
        )
        return 0 if served else 1

    def close(self) -> None:
        if self.store is not None:
            self.store.close()


main = main_for(CgamedStandIn)
