"""Send a transaction (JSON file, or - for stdin) to a running dsr_server and wait for the
verdict: prints the accepted seq (exit 0) or the rejection reason (exit 1)."""

from __future__ import annotations

import argparse
import sys

from dsr_graph.cli.api import DsrError, error
from dsr_graph.formats import safe_json

HELP = "send a transaction; print the accepted seq or the rejection reason"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("file", metavar="FILE", help="transaction JSON, or - to read stdin")
    parser.add_argument(
        "--timeout", type=float, default=10.0, help="seconds to wait for the verdict"
    )


def run(args: argparse.Namespace) -> int:
    from dsr_graph.ros.agent import DsrAgent
    from dsr_graph.ros.session import RosSession

    try:
        text = sys.stdin.read() if args.file == "-" else open(args.file, encoding="utf-8").read()
        doc = safe_json.loads(text, None)
    except (OSError, ValueError) as e:
        return error(f"cannot read a JSON transaction from {args.file}: {e}")
    if not isinstance(doc, dict):
        return error("a transaction is a JSON object")
    results = []
    try:
        with RosSession(ros_args=args.ros_args) as ros:
            agent = DsrAgent(describe=False)  # a one-shot tool
            agent.setup(ros.node, timeout_sec=args.timeout)
            # Wait for the replica too: our delta must not arrive before the stream is matched.
            ros.spin_until(lambda: agent.ready, args.timeout, "the DSR server's topics")
            agent.send(doc, results.append)
            ros.spin_until(lambda: bool(results), args.timeout, "the server's verdict")
    except DsrError as e:
        return error(str(e))
    result = results[0]
    if result.accepted:
        print(f"accepted: seq {result.seq}")
        return 0
    print(f"rejected: {result.error}")
    return 1
