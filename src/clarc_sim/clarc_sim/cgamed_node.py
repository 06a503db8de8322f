"""The CGAmed hospital-server stand-in: the clinician's Start, the results store, the
clinician's notifications, and the clinician's dashboard in the browser (dashboard_app.py).

ROS Parameters: db (SQLite path, default $XDG_DATA_HOME/clarc/cgamed.sqlite), start_patient
(if set, press Start for this patient as soon as PELEA listens), dashboard (true), host
(127.0.0.1), port (8081). Subscriptions: clarc/cgamed/notify, clarc/pelea/events,
clarc/speaker/events. Publishers: clarc/cgamed/start, clarc/cgamed/notifications. Services:
clarc/cgamed/store_result (dsr_msgs/srv/StoreResult).
"""

from __future__ import annotations

import json
import sys
from typing import List, Optional

import rclpy
from clarc_agents import topics
from dsr_graph.node_main import run_node
from dsr_graph.qos import qos_stream
from dsr_graph.web_bridge import Bridge, Broadcaster
from dsr_msgs.srv import StoreResult
from rcl_interfaces.msg import ParameterDescriptor
from rclpy.node import Node
from std_msgs.msg import String

from .dashboard_app import TestStatus, make_app
from .results_store import InvalidResult, ResultsStore, default_db


class CgamedStandIn(Node):
    def __init__(self):
        super().__init__("cgamed")
        self.declare_parameter("db", default_db(), ParameterDescriptor(description="SQLite results store", read_only=True))
        self.declare_parameter("start_patient", "", ParameterDescriptor(description="press Start for this patient"))
        self.declare_parameter("dashboard", True, ParameterDescriptor(description="serve the clinician's dashboard", read_only=True))
        self.declare_parameter("host", "127.0.0.1", ParameterDescriptor(description="dashboard address", read_only=True))
        self.declare_parameter("port", 8081, ParameterDescriptor(description="dashboard port", read_only=True))
        self.status = TestStatus()
        self.events = Broadcaster()
        self.bridge = Bridge(self)
        self._start = self.create_publisher(String, topics.CGAMED_START, qos_stream())
        self._notifications = self.create_publisher(String, topics.CGAMED_NOTIFICATIONS, qos_stream())
        self.store = None
        self._start_timer = None

    def setup(self) -> None:
        self.store = ResultsStore(self.get_parameter("db").value, shared=True)  # used by the ROS thread
        self.create_service(StoreResult, topics.CGAMED_STORE, self.on_store)
        self.create_subscription(String, topics.CGAMED_NOTIFY, self.on_notify, qos_stream())
        self.create_subscription(String, topics.PELEA_EVENTS, self.on_pelea, qos_stream())
        self.create_subscription(String, topics.SPEAKER, self.on_speaker, qos_stream())
        if self.get_parameter("start_patient").value:
            self._start_timer = self.create_timer(0.1, self._press_start_when_heard)
        self.get_logger().info(f"results store: {self.store.path}")

    def press_start(self, patient: str) -> None:
        self._start.publish(String(data=json.dumps({"patient": patient})))
        self.get_logger().info(f"Start pressed for {patient}")

    def _press_start_when_heard(self) -> None:
        if self._start.get_subscription_count() > 0:  # PELEA listens: a Start now is not lost
            self._start_timer.cancel()
            self.press_start(self.get_parameter("start_patient").value)

    def _tell(self, kind: str, message: str, **extra) -> None:
        self.store.notify(kind, message)
        note = {"kind": kind, "message": message, **extra}
        self._notifications.publish(String(data=json.dumps(note)))
        self.bridge.to_web(self.events.publish, "notification", note)
        self.get_logger().info(f"to the clinician: {message}")

    def on_pelea(self, msg: String) -> None:
        try:
            event = json.loads(msg.data)
        except ValueError:
            return
        self.bridge.to_web(self._follow, event)

    def _follow(self, event: dict) -> None:  # web thread
        self.status.follow(event)
        self.events.publish("pelea", event)

    def on_speaker(self, msg: String) -> None:
        try:
            self.bridge.to_web(self.events.publish, "speaker", json.loads(msg.data))
        except ValueError:
            pass

    def on_store(self, request: StoreResult.Request, response: StoreResult.Response):
        try:
            result = json.loads(request.result_json)
            response.test_id = self.store.store(result)
            response.stored = True
        except (ValueError, InvalidResult) as e:
            response.stored, response.error = False, f"result refused: {e}"
            return response
        self._tell("result_stored", f"The Barthel test of {result['patient']} is stored (test {response.test_id}: "
                   f"{result['total']}/100, {result['band']} dependency); please validate it.",
                   test_id=response.test_id, result=result)
        return response

    def on_notify(self, msg: String) -> None:
        try:
            message = str(json.loads(msg.data)["message"])
        except (ValueError, KeyError, TypeError):
            return
        self._tell("clinician_called", message)

    def destroy_node(self) -> None:
        if self.store is not None:
            self.store.close()
        super().destroy_node()


def main(args: Optional[List[str]] = None) -> int:
    def body(node: CgamedStandIn) -> int:
        node.setup()
        if not node.get_parameter("dashboard").value:
            rclpy.spin(node)
            return 0
        app = make_app(node.get_parameter("db").value, node.status, node.events, node.press_start)
        ok = node.bridge.serve(app, node.get_parameter("host").value, node.get_parameter("port").value,
                               on_ready=lambda url: node.get_logger().info(f"clinician's dashboard on {url}"))
        return 0 if ok else 1

    return run_node(CgamedStandIn, body, args)


if __name__ == "__main__":
    sys.exit(main())
