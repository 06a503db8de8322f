"""Print accepted deltas as they come from a running dsr_server: seq, agent and readable ops."""

from __future__ import annotations

import argparse
import json
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

    from dsr_graph.protocol.delta_text import delta_text
    from dsr_graph.protocol.topic_names import DELTAS, REJECTIONS
    from dsr_graph.ros.qos import qos_stream
    from dsr_graph.ros.session import RosSession

    seen = [0]

    def on_delta(msg: String) -> None:
        try:
            delta = json.loads(msg.data)
            print(msg.data if args.json else delta_text(delta), flush=True)
        except (ValueError, KeyError) as e:
            print(f"(unreadable delta: {e})", file=sys.stderr)
        seen[0] += 1

    def on_rejection(msg: String) -> None:
        doc = json.loads(msg.data)
        print(
            msg.data
            if args.json
            else f"rejected {doc.get('id') or '?'} from {doc.get('agent') or '?'}: "
            f"{doc.get('error')}",
            flush=True,
        )

    with RosSession(ros_args=args.ros_args) as ros:
        ros.node.create_subscription(String, DELTAS, on_delta, qos_stream())
        if args.rejections:
            ros.node.create_subscription(String, REJECTIONS, on_rejection, qos_stream())
        ros.follow(lambda: bool(args.count) and seen[0] >= args.count, args.duration)
    return (
        0
        if not args.count or seen[0] >= args.count
        else error(f"saw {seen[0]} of {args.count} deltas")
    )
