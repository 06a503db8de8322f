"""PELEA as a ROS node: the High Level Executive connected to the DSR, the CGAmed start command,
the clinician's notifications and the results store.

ROS Parameters:
    time_scale (float): multiplies every time of the flow (default 1.0: a real session).
    answer_timeout (float): seconds of a real session an answer window stays open (default 8).
    outbox_dir (str): results not yet acknowledged by CGAmed wait here, so a crash loses none
        (default $XDG_STATE_HOME/clarc/pelea_outbox).
Subscriptions: clarc/cgamed/start. Publishers: clarc/pelea/events, clarc/cgamed/notify.
Clients: clarc/cgamed/store_result (dsr_msgs/srv/StoreResult). Plus the DSR topics.
"""

from __future__ import annotations

import json
import os
from datetime import datetime, timezone
from pathlib import Path
from typing import Any, Callable, Dict, Optional

from dsr_graph.agent import DsrAgent
from dsr_graph.qos import qos_stream
from dsr_graph.worldfile import write_json_atomically
from dsr_msgs.srv import StoreResult
from rcl_interfaces.msg import ParameterDescriptor
from rclpy.node import Node
from std_msgs.msg import String

from .. import topics
from ..agent_node import declare_float, get_float, main_for
from .hle import HighLevelExecutive, Times


STORE_TIMEOUT = 5.0  # seconds CGAmed may take to acknowledge a result


def default_outbox() -> str:
    base = os.environ.get("XDG_STATE_HOME") or os.path.join(os.path.expanduser("~"), ".local", "state")
    return os.path.join(base, "clarc", "pelea_outbox")


class _OneShot:
    def __init__(self, node: Node, seconds: float, callback: Callable[[], None]):
        self._node = node
        self._callback = callback
        self._timer = node.create_timer(max(seconds, 0.001), self._fire)

    def _fire(self) -> None:
        self.cancel()
        self._callback()

    def cancel(self) -> None:
        if self._timer is not None:
            self._timer.cancel()
            self._node.destroy_timer(self._timer)
            self._timer = None


class PeleaNode(Node):
    def __init__(self):
        super().__init__("pelea")
        declare_float(self, "time_scale", 1.0, "multiplies every time of the flow")
        declare_float(self, "answer_timeout", 8.0, "seconds of a real session an answer window stays open")
        self.declare_parameter("outbox_dir", default_outbox(), ParameterDescriptor(read_only=True))
        declare_float(self, "setup_timeout", 20.0, "seconds to wait for the DSR server", read_only=True)
        self.dsr = DsrAgent()
        times = Times(scale=get_float(self, "time_scale"), answer_timeout=get_float(self, "answer_timeout"))
        self.hle = HighLevelExecutive(self, times, self.get_logger())
        self.outbox = Path(self.get_parameter("outbox_dir").value)
        self._events = self.create_publisher(String, topics.PELEA_EVENTS, qos_stream())
        self._notify = self.create_publisher(String, topics.CGAMED_NOTIFY, qos_stream())
        self._store = self.create_client(StoreResult, topics.CGAMED_STORE)
        self.create_subscription(String, topics.CGAMED_START, self.on_start, qos_stream())
        self._waiting_start: Optional[str] = None

    def setup(self) -> None:
        self.dsr.setup(self, timeout_sec=get_float(self, "setup_timeout"))
        self.dsr.add_listener(self._on_graph)
        self.outbox.mkdir(parents=True, exist_ok=True)
        self.create_timer(2.0, self._flush_outbox)
        self.get_logger().info("PELEA up: waiting for the clinician's Start")

    def on_start(self, msg: String) -> None:
        try:
            patient = str(json.loads(msg.data)["patient"]).strip()
            if not patient:
                raise ValueError("empty patient name")
        except (ValueError, KeyError, TypeError) as e:
            self.get_logger().error(f"unreadable Start command {msg.data!r}: {e}")
            return
        if not self.dsr.replica.synced:
            self._waiting_start = patient  # start as soon as the replica is there
            return
        self.hle.start(self.dsr.graph, patient)

    def _on_graph(self, deltas, resynced) -> None:
        if self._waiting_start is not None and self.dsr.replica.synced:
            patient, self._waiting_start = self._waiting_start, None
            self.hle.start(self.dsr.graph, patient)
        self.hle.on_graph(self.dsr.graph)

    # ------------------------------------------------------------------ the HLE's port
    def send(self, tx: Dict[str, Any], on_done=None) -> None:
        self.dsr.send(tx, on_done)

    def after(self, seconds: float, callback: Callable[[], None]) -> _OneShot:
        return _OneShot(self, seconds, callback)

    def event(self, **fields: Any) -> None:
        self._events.publish(String(data=json.dumps(fields)))

    def notify_clinician(self, message: str) -> None:
        self._notify.publish(String(data=json.dumps({"message": message})))

    def now(self) -> str:
        return datetime.now(timezone.utc).isoformat(timespec="milliseconds")

    def store_result(self, result: Dict[str, Any], on_done: Callable[[bool, str], None]) -> None:
        # Kept on disk until CGAmed acknowledges it: a crash of PELEA or CGAmed loses nothing.
        path = self.outbox / f"{result['patient']}-{result['started']}.json".replace(":", "").replace("/", "_")
        write_json_atomically(result, path)
        self._send_stored(path, result, on_done)

    def _send_stored(self, path: Path, result: Dict[str, Any], on_done: Callable[[bool, str], None]) -> None:
        if not self._store.service_is_ready():
            on_done(False, "the CGAmed results service is not available")
            return
        future = self._store.call_async(StoreResult.Request(result_json=json.dumps(result)))
        # An unanswered call (CGAmed restarting) is withdrawn and reported, so the HLE retries.
        watchdog = _OneShot(self, STORE_TIMEOUT, lambda: (self._store.remove_pending_request(future),
                                                          on_done(False, f"no answer within {STORE_TIMEOUT} s")))

        def answered(f) -> None:
            watchdog.cancel()
            if f.cancelled():
                return
            try:
                response = f.result()
            except Exception as e:  # noqa: BLE001 - any failure means: not stored, try again
                on_done(False, repr(e))
                return
            if response.stored:
                path.unlink(missing_ok=True)
                self.get_logger().info(f"result stored in CGAmed as test {response.test_id}")
            on_done(response.stored, response.error)

        future.add_done_callback(answered)

    def _flush_outbox(self) -> None:
        """Results left by an earlier run (crash before CGAmed answered) are sent again."""
        if self.hle.running:
            return
        for path in sorted(self.outbox.glob("*.json")):
            try:
                result = json.loads(path.read_text())
            except (OSError, ValueError) as e:
                self.get_logger().error(f"unreadable result in the outbox {path}: {e}")
                continue
            self._send_stored(path, result, lambda ok, error: None)


main = main_for(PeleaNode)
