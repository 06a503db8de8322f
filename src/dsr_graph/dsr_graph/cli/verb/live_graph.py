"""Print the live graph of a running dsr_server (through the snapshot service)."""

from __future__ import annotations

import argparse
import json

from dsr_graph.cli.api import DsrError, error, live_graph, with_snapshot
from dsr_graph.model.binary import short_text

NAME = "graph"
HELP = "print the live graph (nodes, edges, RT tree); --json for the snapshot"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--json", action="store_true", help="print the snapshot JSON")
    parser.add_argument(
        "--timeout", type=float, default=10.0, help="seconds to wait for the server"
    )


def run(args: argparse.Namespace) -> int:
    try:
        return with_snapshot(args.timeout, args.ros_args, lambda doc: show(doc, args.json))
    except DsrError as e:
        return error(str(e))


def show(doc: dict, as_json: bool) -> int:
    if as_json:
        print(json.dumps(doc, indent=2))
        return 0
    try:
        graph, seq = live_graph(doc)
    except DsrError as e:
        return error(str(e))
    print(f"seq {seq}: {len(graph)} nodes, {graph.edge_count()} edges")
    for node in sorted(graph.nodes(), key=lambda n: n.id):
        parent = graph.rt_parent(node.id)
        where = f"  RT parent {parent.name}" if parent else ""
        attrs = ", ".join(f"{k}={short_text(v)}" for k, v in node.attrs.items())
        print(
            f"  [{node.id}] {node.name} : {node.type}  v{node.version}{where}"
            + (f"  {{{attrs}}}" if attrs else "")
        )
    for edge in sorted(graph.edges(), key=lambda e: (e.src, e.dst, e.type)):
        if edge.type != "RT":
            attrs = ", ".join(f"{k}={short_text(v)}" for k, v in edge.attrs.items())
            print(
                f"  {graph.node(edge.src).name} -{edge.type}-> {graph.node(edge.dst).name}"
                + (f"  {{{attrs}}}" if attrs else "")
            )
    for c in doc.get("claims", []):
        print(f"  claim {json.dumps(c['target'])} by {c['agent']} (priority {c['priority']})")
    return 0
