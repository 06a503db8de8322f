"""Print the live graph of a running dsr_server (through the snapshot service)."""

from __future__ import annotations

import argparse
import json

from . import DsrError, error
from .. import dsr_format

HELP = "print the live graph (nodes, edges, RT tree); --json for the snapshot"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--json", action="store_true", help="print the snapshot JSON")
    parser.add_argument("--timeout", type=float, default=10.0, help="seconds to wait for the server")


def fetch_snapshot(timeout: float) -> dict:
    from dsr_msgs.srv import GetSnapshot

    from ..ros_session import RosSession
    from ..topic_names import GET_SNAPSHOT

    with RosSession() as ros:
        client = ros.node.create_client(GetSnapshot, GET_SNAPSHOT)
        return json.loads(ros.call(client, GetSnapshot.Request(), timeout, "the snapshot").snapshot_json)


def run(args: argparse.Namespace) -> int:
    try:
        doc = fetch_snapshot(args.timeout)
    except DsrError as e:
        return error(str(e))
    if args.json:
        print(json.dumps(doc, indent=2))
        return 0
    graph, seq = dsr_format.snapshot_from_json(doc)
    print(f"seq {seq}: {len(graph)} nodes, {graph.edge_count()} edges")
    for node in sorted(graph.nodes(), key=lambda n: n.id):
        parent = graph.rt_parent(node.id)
        where = f"  RT parent {parent.name}" if parent else ""
        attrs = ", ".join(f"{k}={json.dumps(v)}" for k, v in node.attrs.items())
        print(f"  [{node.id}] {node.name} : {node.type}  v{node.version}{where}" + (f"  {{{attrs}}}" if attrs else ""))
    for edge in sorted(graph.edges(), key=lambda e: (e.src, e.dst, e.type)):
        if edge.type != "RT":
            attrs = ", ".join(f"{k}={json.dumps(v)}" for k, v in edge.attrs.items())
            print(f"  {graph.node(edge.src).name} -{edge.type}-> {graph.node(edge.dst).name}" + (f"  {{{attrs}}}" if attrs else ""))
    for c in doc.get("claims", []):
        print(f"  claim {json.dumps(c['target'])} by {c['agent']} (priority {c['priority']})")
    return 0
