"""ROS introspection without the ros2 command line (not installable from PyPI): the nodes,
topics with their types and services with their types that this machine's ROS graph shows."""

from __future__ import annotations

import argparse
import json

HELP = "list ROS nodes, topics (with types) and services (like ros2 node/topic/service list)"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--json", action="store_true")
    parser.add_argument("--wait", type=float, default=1.5, help="seconds to let discovery run (default 1.5)")


def run(args: argparse.Namespace) -> int:
    from ..ros_session import RosSession
    from ..topic_names import POSE_PREFIX

    with RosSession() as ros:
        ros.spin_for(args.wait)
        me = ros.node.get_fully_qualified_name()
        nodes = sorted({(ns.rstrip("/") + "/" + n) for n, ns in ros.node.get_node_names_and_namespaces()} - {me})
        topics = sorted(ros.node.get_topic_names_and_types())
        services = sorted((name, types) for name, types in ros.node.get_service_names_and_types()
                          if not name.startswith(me + "/"))
    if args.json:
        print(json.dumps({"nodes": nodes,
                          "topics": [{"name": n, "types": t} for n, t in topics],
                          "services": [{"name": n, "types": t} for n, t in services]}, indent=2))
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
