"""Print the messages of a JSON topic (std_msgs/String carrying JSON, as every topic of the suite
does): whole messages, or only some fields. What ``ros2 topic echo`` would give, which is not
installable from PyPI; the subscription takes the publishers' reliability and durability, so a
latched topic (dsr/heartbeat) shows its last message and a sensor stream (best effort) is heard.
"""

from __future__ import annotations

import argparse
import json
from typing import Any

from dsr_graph.cli.api import error
from dsr_graph.formats import safe_json

HELP = "print a JSON topic's messages (whole, or --field a.b) like ros2 topic echo"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("topic", metavar="TOPIC", help="e.g. dsr/deltas or /clarc/pelea/events")
    parser.add_argument(
        "--field",
        action="append",
        default=[],
        metavar="PATH",
        help="print only this field (dots for nesting, numbers for list items: ops.0.op); "
        "may be given more than once",
    )
    parser.add_argument("--count", type=int, default=0, help="exit after this many messages")
    parser.add_argument("--duration", type=float, default=0.0, help="exit after this many seconds")
    parser.add_argument("--pretty", action="store_true", help="indented JSON")


def field(doc: Any, path: str) -> Any:
    """``doc``'s value at a dotted ``path``; KeyError naming the missing step."""
    value = doc
    for step in path.split("."):
        if isinstance(value, list) and step.lstrip("-").isdigit():
            index = int(step)
            if not -len(value) <= index < len(value):
                raise KeyError(f"{path}: no item {step}")
            value = value[index]
        elif isinstance(value, dict) and step in value:
            value = value[step]
        else:
            raise KeyError(f"{path}: no {step!r}")
    return value


def render(text: str, fields: list[str], pretty: bool) -> str:
    """One message as printed: the JSON (or the chosen fields), or the text if it is not JSON."""
    try:
        doc = safe_json.loads(text, None)  # a hostile message is shown as text, never a crash
    except ValueError:
        return text
    if fields:
        chosen = {}
        for path in fields:
            try:
                chosen[path] = field(doc, path)
            except KeyError as e:
                chosen[path] = f"(missing: {e.args[0]})"
        doc = chosen[fields[0]] if len(fields) == 1 else chosen
    return json.dumps(doc, indent=2 if pretty else None, ensure_ascii=False)


def run(args: argparse.Namespace) -> int:
    from std_msgs.msg import String

    from dsr_graph.ros.qos import qos_matching
    from dsr_graph.ros.session import RosSession

    seen = [0]

    def on_message(msg: String) -> None:
        print(render(msg.data, args.field, args.pretty), flush=True)
        seen[0] += 1

    with RosSession(ros_args=args.ros_args) as ros:
        topic = ros.node.resolve_topic_name(args.topic)
        ros.spin_for(0.5)  # discovery: whose publishers are there, and with which QoS
        publishers = ros.node.get_publishers_info_by_topic(topic)
        types = {t for p in publishers for t in [p.topic_type]}
        if types - {"std_msgs/msg/String"}:
            return error(
                f"{topic} is of type {', '.join(sorted(types))}; dsr echo shows "
                "std_msgs/String topics (JSON)"
            )
        ros.node.create_subscription(String, topic, on_message, qos_matching(publishers))
        ros.follow(lambda: bool(args.count) and seen[0] >= args.count, args.duration)
    if args.count and seen[0] < args.count:
        return error(f"saw {seen[0]} of {args.count} messages on {topic}")
    return 0
