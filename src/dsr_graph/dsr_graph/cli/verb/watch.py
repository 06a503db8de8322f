"""Print accepted deltas as they come from a running dsr_server: seq, agent and readable ops."""

from __future__ import annotations

import argparse
import sys

from dsr_graph.cli.api import error

HELP = "follow accepted deltas live (seq, agent, ops); --json for raw deltas"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--json", action="store_true", help="print each delta as one JSON line")
    parser.add_argument("--rejections", action="store_true", help="also print rejected requests")
    parser.add_argument(
        "--count", type=int, default=0, help="exit after this many deltas (default: never)"
    )
    parser.add_argument(
        "--duration", type=float, default=0.0, help="exit after this many seconds (default: never)"
    )


def run(args: argparse.Namespace) -> int:
    from std_msgs.msg import String

    from dsr_graph.formats.safe_json import loads_object
    from dsr_graph.protocol.delta_text import delta_text
    from dsr_graph.protocol.security import Security
    from dsr_graph.protocol.topic_names import DELTAS, REJECTIONS
    from dsr_graph.ros.qos import qos_stream
    from dsr_graph.ros.session import RosSession

    seen = [0]
    security = [None]

    def opened(channel: str, text: str) -> str | None:
        text_or_none, problem = security[0].from_server(channel, text)
        if problem:
            dropped = "dropped" if text_or_none is None else "shown (permissive)"
            print(f"(a message the DSR server did not sign, {dropped}: {problem})", file=sys.stderr)
        return text_or_none

    def on_delta(msg: String) -> None:
        text = opened(DELTAS, msg.data)
        if text is None:
            return
        try:
            delta = loads_object(text, None)
            print(msg.data if args.json else delta_text(delta), flush=True)
        except (ValueError, KeyError, TypeError) as e:
            print(f"(unreadable delta: {e})", file=sys.stderr)
        seen[0] += 1

    def on_rejection(msg: String) -> None:
        text = opened(REJECTIONS, msg.data)
        try:
            doc = loads_object(text) if text is not None else None
        except ValueError as e:
            print(f"(unreadable rejection: {e})", file=sys.stderr)
            return
        if doc is None:
            return
        print(
            msg.data
            if args.json
            else f"rejected {doc.get('id') or '?'} from {doc.get('agent') or '?'}: "
            f"{doc.get('error')}",
            flush=True,
        )

    with RosSession(ros_args=args.ros_args) as ros:
        security[0] = Security.from_environment(ros.node.get_fully_qualified_name())
        ros.node.create_subscription(String, DELTAS, on_delta, qos_stream())
        if args.rejections:
            ros.node.create_subscription(String, REJECTIONS, on_rejection, qos_stream())
        ros.follow(lambda: bool(args.count) and seen[0] >= args.count, args.duration)
    return (
        0
        if not args.count or seen[0] >= args.count
        else error(f"saw {seen[0]} of {args.count} deltas")
    )
