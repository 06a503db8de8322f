"""The CGAmed hospital-server stand-in: the clinician's Start, the results store, and the
clinician's notifications.

ROS Parameters: db (SQLite path, default $XDG_DATA_HOME/clarc/cgamed.sqlite), start_patient
(if set, press Start for this patient as soon as PELEA listens). Subscriptions:
clarc/cgamed/notify. Publishers: clarc/cgamed/start, clarc/cgamed/notifications. Services:
clarc/cgamed/store_result (dsr_msgs/srv/StoreResult).
"""

from __future__ import annotations

import json

from clarc_agents import topics
from clarc_agents.agent_node import main_for
from dsr_msgs.srv import StoreResult
from dsr_graph.qos import qos_stream
from rcl_interfaces.msg import ParameterDescriptor
from rclpy.node import Node
from std_msgs.msg import String

from .results_store import InvalidResult, ResultsStore, default_db


class CgamedStandIn(Node):
    def __init__(self):
        super().__init__("cgamed")
        self.declare_parameter("db", default_db(), ParameterDescriptor(description="SQLite results store", read_only=True))
        self.declare_parameter("start_patient", "", ParameterDescriptor(description="press Start for this patient"))
        self._start = self.create_publisher(String, topics.CGAMED_START, qos_stream())
        self._notifications = self.create_publisher(String, topics.CGAMED_NOTIFICATIONS, qos_stream())
        self.store = None
        self._start_timer = None

    def setup(self) -> None:
        self.store = ResultsStore(self.get_parameter("db").value)
        self.create_service(StoreResult, topics.CGAMED_STORE, self.on_store)
        self.create_subscription(String, topics.CGAMED_NOTIFY, self.on_notify, qos_stream())
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
        self._notifications.publish(String(data=json.dumps({"kind": kind, "message": message, **extra})))
        self.get_logger().info(f"to the clinician: {message}")

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


main = main_for(CgamedStandIn)
