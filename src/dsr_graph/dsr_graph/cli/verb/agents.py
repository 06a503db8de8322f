"""The agents a running dsr_server's graph describes (their agent info nodes,
model/agent_info.py): name, state, process and what each does and listens to."""

from __future__ import annotations

import argparse
import json

from dsr_graph.cli.api import DsrError, error, live_graph, with_snapshot
from dsr_graph.model.agent_info import listing

HELP = "the agents in the graph and their states (starting, ready, gone); --json"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--json", action="store_true", help="print them as a JSON list")
    parser.add_argument(
        "--timeout", type=float, default=10.0, help="seconds to wait for the server"
    )


def run(args: argparse.Namespace) -> int:
    try:
        return with_snapshot(args.timeout, args.ros_args, lambda doc: show(doc, args.json))
    except DsrError as e:
        return error(str(e))


def show(doc: dict, as_json: bool) -> int:
    graph, _seq = live_graph(doc)
    agents = listing(graph)
    if as_json:
        print(json.dumps(agents, indent=2))
        return 0
    if not agents:
        print("no agent has described itself in the graph")
        return 0
    width = max(len(a["name"]) for a in agents)
    for a in agents:
        process = f"pid {a.get('pid', '?')} on {a.get('host', '?')}"
        does = f"  does: {', '.join(a['can_do'])}" if a.get("can_do") else ""
        listens = f"  listens to: {', '.join(a['listens_to'])}" if a.get("listens_to") else ""
        print(f"{a['name']:<{width}}  {a['state']:<8}  {process}{does}{listens}")
    return 0
