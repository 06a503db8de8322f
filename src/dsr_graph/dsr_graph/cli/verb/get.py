"""Read a node, or one of its attributes, from a running dsr_server (through its services)."""

from __future__ import annotations

import argparse
import json

from dsr_graph.cli.api import DsrError, error
from dsr_graph.formats import safe_json

HELP = "read a node (all of it) or one attribute from the live graph"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("node", metavar="NODE", help="node name")
    parser.add_argument(
        "attr", metavar="ATTR", nargs="?", help="attribute name (omit for the whole node)"
    )
    parser.add_argument(
        "--edge", nargs=2, metavar=("TO", "TYPE"), help="read ATTR of the edge NODE -TYPE-> TO"
    )
    parser.add_argument(
        "--provenance",
        action="store_true",
        help="also say who wrote each attribute and when (time: seconds since the epoch)",
    )
    parser.add_argument(
        "--timeout", type=float, default=10.0, help="seconds to wait for the server"
    )


def _without_provenance(doc: dict) -> dict:
    doc.pop("provenance", None)
    for edge in doc.get("out", []) + doc.get("in", []):
        edge.pop("provenance", None)
    return doc


def _provenance_of(doc: dict, attr: str, edge: list[str] | None) -> dict | None:
    """An attribute's {"time", "agent"} in a node's answer (of one of its edges with --edge; the
    transform of an RT edge is "rt")."""
    holder = doc
    if edge:
        to, type = edge
        holder = next((e for e in doc["out"] if e["to"] == to and e["type"] == type), {})
        attr = "$rt" if type == "RT" and attr == "rt" else attr
    return holder.get("provenance", {}).get(attr)


def run(args: argparse.Namespace) -> int:
    from dsr_graph.protocol.topic_names import GET_ATTRIBUTE, GET_NODE
    from dsr_graph.ros.session import RosSession
    from dsr_msgs.srv import GetAttribute, GetNode

    if args.edge and not args.attr:
        return error("--edge needs ATTR")
    try:
        with RosSession(ros_args=args.ros_args) as ros:
            if args.attr is None:
                client = ros.node.create_client(GetNode, GET_NODE)
                answer = ros.call(client, GetNode.Request(node=args.node), args.timeout, "the node")
                if not answer.found:
                    return error(answer.error)
                doc = safe_json.loads(answer.node_json, None)
                if not args.provenance:
                    doc = _without_provenance(doc)
                print(json.dumps(doc, indent=2))
                return 0
            client = ros.node.create_client(GetAttribute, GET_ATTRIBUTE)
            request = GetAttribute.Request(
                node=args.node,
                attribute=args.attr,
                edge_to=args.edge[0] if args.edge else "",
                edge_type=args.edge[1] if args.edge else "",
            )
            answer = ros.call(client, request, args.timeout, "the attribute")
            shown = {}
            if answer.found and args.provenance:
                node_client = ros.node.create_client(GetNode, GET_NODE)
                whole = ros.call(node_client, GetNode.Request(node=args.node), args.timeout, "")
                if whole.found:
                    doc = safe_json.loads(whole.node_json, None)
                    shown = {"provenance": _provenance_of(doc, args.attr, args.edge)}
    except DsrError as e:
        return error(str(e))
    if not answer.found:
        return error(answer.error)
    print(
        json.dumps(
            {
                "value": safe_json.loads(answer.value_json, None),
                "type": answer.value_type,
                "version": answer.version,
                "seq": answer.seq,
                **shown,
            }
        )
    )
    return 0
