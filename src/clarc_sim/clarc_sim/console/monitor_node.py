"""The launch's screen: one readable line per step of the test (what CLARC says, answers, the
person leaving, the clinician called, replanning), the result at the end. Exits 0 when CGAmed
has stored the result, 1 if PELEA reports an error or nothing finishes within ``timeout``.

ROS Parameters: timeout (seconds, default 600). Subscriptions: clarc/speaker/events,
clarc/pelea/events, clarc/cgamed/notifications.
"""

from __future__ import annotations

import time
from typing import Any

import rclpy

from clarc_agents import topics
from dsr_graph.ros.dsr_node import DsrNode, main_for
from dsr_graph.ros.json_topics import subscribe_json
from dsr_graph.ros.parameters import declare, float_param, param
from dsr_graph.ros.qos import qos_stream


def describe_event(event: dict) -> str | None:
    kind = event.get("event")
    if kind == "started":
        return f"Start pressed: Barthel test for {event['patient']}"
    if kind == "item":
        return f"--- item {event['position']}/10: {event['item']}"
    if kind == "answer":
        return f"answer: {event['item']} = {event['points']} points, by {event['via']}"
    if kind == "no_answer":
        return f"no answer to {event['item']} in time (try {event['window']})"
    if kind == "not_understood":
        return f"not understood: {event['heard']!r} (try {event['window']})"
    if kind == "skip":
        return f"the patient asked to skip {event['item']}"
    if kind == "unanswered":
        return f"{event['item']} left unanswered"
    if kind == "person_lost":
        return "the person left"
    if kind == "person_back":
        return "the person is back"
    if kind == "clinician_called":
        return f"the clinician is called ({', '.join(event['unanswered'])} unanswered)"
    if kind == "plan" and event.get("reason") != "start":
        return f"PELEA replans: {event['reason']} -> {event['first']} ({event['steps']} actions)"
    if kind == "plan":
        return f"PELEA plans {event['steps']} actions"
    if kind in ("warning", "error"):
        return f"{kind}: {event['message']}"
    return None


def describe_result(result: dict) -> list[str]:
    lines = [
        f"RESULT {result['patient']}: Barthel index {result['total']}/100 "
        f"({result['band']} dependency)"
    ]
    for i in result["items"]:
        got = "unanswered" if i["points"] is None else f"{i['points']:>2} points by {i['via']}"
        lines.append(f"  {i['item']:<11} {got}  ({i['attempts']} tries)")
    lines.append(
        f"  clinician called: {'yes' if result['clinician_called'] else 'no'}; "
        f"person left: {result.get('person_lost_count', 0)} time(s)"
    )
    return lines


class Monitor(DsrNode):
    def __init__(self):
        super().__init__("clarc_monitor")
        declare(self, "timeout", 600.0, "seconds before giving up", read_only=True, minimum=0.0)
        self.t0 = time.monotonic()
        self.exit_code: int | None = None

    def setup(self) -> None:
        subscribe_json(self, topics.SPEAKER, self.on_speaker, qos_stream())
        subscribe_json(self, topics.PELEA_EVENTS, self.on_pelea, qos_stream())
        subscribe_json(self, topics.CGAMED_NOTIFICATIONS, self.on_notification, qos_stream())

    def say(self, line: str) -> None:
        print(f"[{time.monotonic() - self.t0:6.1f}s] {line}", flush=True)

    def on_speaker(self, event: dict[str, Any]) -> None:
        if event["event"] == "start":
            self.say(f"CLARC: {event['text']}")
        elif event["event"] == "stopped":
            self.say("CLARC stops talking")

    def on_pelea(self, event: dict[str, Any]) -> None:
        line = describe_event(event)
        if line:
            self.say(line)
        if event.get("event") == "error":
            self.exit_code = 1

    def on_notification(self, note: dict[str, Any]) -> None:
        self.say(f"to the clinician: {note['message']}")
        if note.get("kind") == "result_stored":
            for line in describe_result(note["result"]):
                print(line, flush=True)
            self.exit_code = 0

    def run(self) -> int:
        """Exit 0 once the result is stored, 1 on PELEA's error or after ``timeout``."""
        deadline = time.monotonic() + float_param(self, "timeout")
        while self.exit_code is None and time.monotonic() < deadline:
            rclpy.spin_once(self, timeout_sec=0.1)
        if self.exit_code is None:
            self.say(f"the test did not finish within {param(self, 'timeout')} s")
            return 1
        return self.exit_code


main = main_for(Monitor)
