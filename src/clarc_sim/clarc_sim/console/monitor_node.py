"""The launch's screen: one readable line per step of the test, the result at the end. The steps
are read from the DSR (clarc_agents/course.py), so the screen stays right across a restart of
PELEA, of the DSR server or of the monitor itself; PELEA's own stream adds only what is PELEA's
(plans, replans, warnings, errors), the speaker what CLARC says, CGAmed what it tells the
clinician, the ROS graph which of the robot's nodes are in reach (a node that died, or a
network cut between hosts). Exits 0 once a test started at or after ``since`` is finished in
the DSR (PELEA writes that only after CGAmed stored its result), 1 on PELEA's error or after
``timeout``, saying then where each agent stands (its state in the DSR, or a ROS node that never
joined it).

ROS Parameters: timeout (seconds, default 600), since (ISO 8601; default: when the monitor
started), setup_timeout (seconds). Subscriptions: the DSR's topics (dsr/alarms too: each alarm
a member of the keystore signed is printed), clarc/speaker/events, clarc/pelea/events,
clarc/cgamed/notifications.
"""

from __future__ import annotations

import time
from datetime import UTC, datetime
from typing import Any

from std_msgs.msg import String

from clarc_agents import topics
from clarc_agents.course import Course, band_words, test_name
from clarc_sim.console.reach import HeartbeatSilence, Reach, where_agents_stand
from dsr_graph.formats.safe_json import loads_object
from dsr_graph.model.agent_info import listing
from dsr_graph.protocol import topic_names
from dsr_graph.ros.agent import SERVER_SILENCE, DsrAgent
from dsr_graph.ros.dsr_node import DsrNode, main_for
from dsr_graph.ros.json_topics import subscribe_json
from dsr_graph.ros.parameters import declare, declare_setup_timeout, float_param, param
from dsr_graph.ros.qos import qos_stream


def describe_step(event: dict) -> str | None:
    """A step of the test read from the DSR (course.py's events) as one line."""
    kind = event.get("event")
    if kind == "start_requested":
        return f"Start pressed for {event['patient']}"
    if kind == "started":
        return f"{test_name(event.get('test', 'barthel'))} started for {event['patient']}"
    if kind == "trial":
        return f"--- trial {event['trial']}: go!"
    if kind == "phase":
        return f"the patient is in the {event['phase'].replace('_', ' ')} phase"
    if kind == "timed":
        return f"trial {event['trial']} timed: {event['tug_seconds']} s ({event['band']})"
    if kind == "trial_void":
        return f"trial {event['trial']} is void: it will be repeated if trials are left"
    if kind == "following":
        return (
            f"following the {test_name(event.get('test', 'barthel'))} of {event['patient']} "
            f"under way (item {event['position']}/{event.get('of', 10)}: {event['item']})"
        )
    if kind == "item":
        return f"--- item {event['position']}/{event.get('of', 10)}: {event['item']}"
    if kind == "answer" and event["points"] is None:
        return f"answer: {event['item']} drawn, by {event['via']}: the clinician scores it"
    if kind == "answer":
        return f"answer: {event['item']} = {event['points']} points, by {event['via']}"
    if kind == "no_answer":
        return f"no answer to {event['item']} in time (try {event['attempt']})"
    if kind == "not_understood":
        return f"not understood: {event['heard']!r} (try {event['attempt']})"
    if kind == "unsure":
        return f"heard {event['heard']!r}, not for sure: asking whether it was meant"
    if kind == "skip":
        return f"the patient asked to skip {event['item']}"
    if kind == "window_interrupted":
        return (
            f"{event['item']}: no one could hear the answer (a restart, a network cut); asked again"
        )
    if kind == "unanswered":
        return f"{event['item']} left unanswered"
    if kind == "person_lost":
        return "the person left"
    if kind == "person_back":
        return "the person is back"
    if kind == "clinician_called" and event["unanswered"]:
        return f"the clinician is called ({', '.join(event['unanswered'])} unanswered)"
    if kind == "clinician_called":
        return "the clinician is called"
    return None


def describe_pelea(event: dict) -> str | None:
    """What only PELEA knows: its plans and replans, its warnings and errors."""
    kind = event.get("event")
    if kind == "plan" and event.get("reason") != "start":
        return f"PELEA replans: {event['reason']} -> {event['first']} ({event['steps']} actions)"
    if kind == "plan":
        return f"PELEA plans {event['steps']} actions"
    if kind in ("warning", "error"):
        return f"{kind}: {event['message']}"
    return None


def describe_result(result: dict) -> list[str]:
    if result.get("test") == "get_up_and_go":
        if not result.get("tug_seconds"):
            reasons = [f"  {r}" for r in result.get("void_reasons", [])]
            return [
                f"RESULT {result['patient']}: Get Up & Go unable to perform "
                "(the clinician is called)",
                *reasons,
            ]
        risk = ", fall risk" if result["fall_risk"] else ""
        phases = ", ".join(f"{p.replace('_', ' ')} {s:.1f} s" for p, s in result["phases"].items())
        return [
            f"RESULT {result['patient']}: Get Up & Go {result['tug_seconds']:.1f} s "
            f"({result['band']}{risk})",
            f"  reaction {result.get('reaction_seconds', 0.0):.1f} s, {phases}",
            f"  trials: {result['trials']}; person left: {result['person_lost_count']} time(s)",
        ]
    test = result.get("test", "barthel")
    if test == "barthel":
        score = f"Barthel index {result['total']}/100 ({band_words(result)})"
    else:
        waiting = [i["item"] for i in result["items"] if i["needs_clinician"] and i["via"]]
        score = f"{test_name(test)} {result['total']}/{result['max_total']} ({band_words(result)})"
        score += f"; the clinician scores {', '.join(waiting)}" if waiting else ""
    lines = [f"RESULT {result['patient']}: {score}"]
    width = max(11, *(len(i["item"]) for i in result["items"]))
    for i in result["items"]:
        if i["points"] is not None:
            got = f"{i['points']:>2} points by {i['via']}"
        elif i["via"]:
            got = f"drawn by {i['via']}, to score"
        elif i.get("needs_clinician"):  # heard, never understood: the clinician's, with clips
            got = f"not understood, to score ({len(i.get('audio', []))} clips)"
        else:
            got = "unanswered"
        lines.append(f"  {i['item']:<{width}} {got}  ({i['attempts']} tries)")
    lines.append(
        f"  clinician called: {'yes' if result['clinician_called'] else 'no'}; "
        f"person left: {result.get('person_lost_count', 0)} time(s)"
    )
    return lines


REACH_PERIOD = 0.5  # seconds between looks at the ROS graph and at the server's heartbeat
ROBOT_NODES = [  # the robot's nodes whose reach the monitor shows
    "/dsr_server",
    "/pelea",
    "/speech",
    "/panel",
    "/person",
    "/tts",
    "/microphone",
    "/touchscreen",
    "/kinect",
    "/patient",
    "/cgamed",
]


class Monitor(DsrNode):
    NAME = "clarc_monitor"

    @classmethod
    def declare_node_parameters(cls, node) -> None:
        declare(node, "timeout", 600.0, "seconds before giving up", read_only=True, minimum=0.0)
        declare(
            node,
            "since",
            "",
            "ISO 8601: a test started from then is this run's (default: the monitor's start)",
            read_only=True,
        )
        declare_setup_timeout(node, 20.0)

    def __init__(self):
        super().__init__()
        self.t0 = time.monotonic()
        self.exit_code: int | None = None
        self.dsr = DsrAgent(describe=False)  # reads, never writes
        self.course: Course | None = None
        self.reach = Reach(ROBOT_NODES)
        self.silence = HeartbeatSilence(SERVER_SILENCE)

    def setup(self) -> None:
        since = param(self, "since") or datetime.now(UTC).isoformat()
        try:
            moment = datetime.fromisoformat(since)
        except ValueError as e:  # reported by main_for, naming the parameter
            raise ValueError(f"parameter since: not an ISO 8601 time: {since!r}") from e
        self.course = Course(moment if moment.tzinfo else moment.astimezone())  # naive: local
        subscribe_json(self, topics.SPEAKER, self.on_speaker, qos_stream())
        subscribe_json(self, topics.PELEA_EVENTS, self.on_pelea, qos_stream())
        subscribe_json(self, topics.CGAMED_NOTIFICATIONS, self.on_notification, qos_stream())
        self.dsr.setup(self, timeout_sec=float_param(self, "setup_timeout"))
        self.dsr.add_listener(lambda deltas, resynced: self.on_graph())
        self.create_subscription(String, topic_names.ALARMS, self.on_alarm, qos_stream())
        self.create_timer(REACH_PERIOD, self.on_reach)

    def _listed(self) -> list[str]:
        """The ROS graph's nodes, fully qualified."""
        return [f"{ns.rstrip('/')}/{name}" for name, ns in self.get_node_names_and_namespaces()]

    def on_reach(self) -> None:
        for line in self.reach.update(self._listed()):
            self.say(line)
        # (scripts/two_hosts.sh runs the monitor on the other host than the server's)
        line = self.silence.update(self.dsr.heard, time.monotonic())
        if line:
            self.say(line)

    def say(self, line: str) -> None:
        print(f"[{time.monotonic() - self.t0:6.1f}s] {line}", flush=True)

    def on_graph(self) -> None:
        for step in self.course.follow(self.dsr.graph):
            line = describe_step(step)
            if line:
                self.say(line)
            if step["event"] == "finished" and self.exit_code is None:
                for line in describe_result(step["result"]):
                    print(line, flush=True)
                self.exit_code = 0

    def on_speaker(self, event: dict[str, Any]) -> None:
        if event["event"] == "start":
            self.say(f"CLARC: {event['text']}")
        elif event["event"] == "stopped":
            self.say("CLARC stops talking")

    def on_pelea(self, event: dict[str, Any]) -> None:
        line = describe_pelea(event)
        if line:
            self.say(line)
        if event.get("event") == "error":
            self.exit_code = 1

    def on_alarm(self, msg: String) -> None:
        """The DSR's alarms (a forged message, a node taking another's topic), when a member of
        the keystore signed them (under DSR security: anyone could forge an alarm too)."""
        text, _ = self.dsr.security.from_member(topic_names.ALARMS, msg.data)
        try:
            alarm = loads_object(text) if text is not None else None
        except ValueError:
            return
        if alarm is not None:
            self.say(f"ALARM ({alarm.get('kind', '?')}): {alarm.get('message', '')}")

    def on_notification(self, note: dict[str, Any]) -> None:
        self.say(f"to the clinician: {note['message']}")

    def run(self) -> int:
        """Exit 0 once this run's test is finished in the DSR, 1 on PELEA's error or after
        ``timeout``."""
        deadline = time.monotonic() + float_param(self, "timeout")
        while self.exit_code is None and time.monotonic() < deadline:
            if self.stop_requested():
                return 0
            self.spin_once(0.1)
        if self.exit_code is None:
            self.say(f"the test did not finish within {param(self, 'timeout')} s")
            self.say(where_agents_stand(listing(self.dsr.graph), self._listed()))
            return 1
        return self.exit_code


main = main_for(Monitor)
