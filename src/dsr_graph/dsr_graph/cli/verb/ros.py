"""ROS introspection without the ros2 command line (not installable from PyPI): the nodes,
topics with their types and services with their types that this machine's ROS graph shows."""

from __future__ import annotations

import argparse
import json
import time

HELP = "list ROS nodes, topics (with types) and services (like ros2 node/topic/service list)"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--json", action="store_true")
    parser.add_argument(
        "--wait",
        type=float,
        default=5.0,
        help="at most this many seconds of discovery; it stops earlier once the graph has been "
        "stable for a second (default 5)",
    )


def run(args: argparse.Namespace) -> int:
    from dsr_graph.protocol.topic_names import POSE_PREFIX
    from dsr_graph.ros.session import RosSession

    with RosSession(ros_args=args.ros_args) as ros:
        me = ros.node.get_fully_qualified_name()

        def look():
            nodes = sorted(
                {(ns.rstrip("/") + "/" + n) for n, ns in ros.node.get_node_names_and_namespaces()}
                - {me}
            )
            topics = sorted(ros.node.get_topic_names_and_types())
            services = sorted(
                (name, types)
                for name, types in ros.node.get_service_names_and_types()
                if not name.startswith(me + "/")
            )
            return nodes, topics, services

        # Discovery has no "done" signal: look until nothing new appeared for a second.
        start = time.monotonic()
        seen, stable_since = look(), time.monotonic()
        while time.monotonic() - start < args.wait:
            ros.spin_for(0.1)
            now = look()
            if now != seen:
                seen, stable_since = now, time.monotonic()
            elif (
                time.monotonic() - stable_since >= 1.0
                and time.monotonic() - start >= 1.0
                and seen[0]
            ):
                break
        nodes, topics, services = seen
    if args.json:
        print(
            json.dumps(
                {
                    "nodes": nodes,
                    "topics": [{"name": n, "types": t} for n, t in topics],
                    "services": [{"name": n, "types": t} for n, t in services],
                },
                indent=2,
            )
        )
        return 0
    print(f"nodes ({len(nodes)}):")
    for n in nodes:
        print(f"  {n}")
    poses = [t for t in topics if t[0].startswith("/" + POSE_PREFIX + "/")]
    print(f"topics ({len(topics)}, of which {len(poses)} poses):")
    for name, types in topics:
        print(f"  {name}  [{', '.join(types)}]")
    print(f"services ({len(services)}):")
    for name, types in services:
        print(f"  {name}  [{', '.join(types)}]")
    return 0
