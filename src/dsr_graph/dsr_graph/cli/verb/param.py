"""List, read and change a running node's parameters through its standard parameter services
(rcl_interfaces): what ``ros2 param list|get|set|describe`` would give, which is not installable
from PyPI. A value is written as on the command line (``-p name:=value``): YAML, so ``2`` is an
integer, ``2.0`` a float, ``true`` a bool, ``[1.0, 2.0]`` a list. The node refuses what its
descriptor forbids (read-only, out of range) and the reason is printed.
"""

from __future__ import annotations

import argparse
import json

from dsr_graph.cli.api import DsrError, error

HELP = "list, get, set or describe a running node's parameters (like ros2 param)"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("action", choices=("list", "get", "set", "describe"))
    parser.add_argument("node", metavar="NODE", help="node name, e.g. pelea or /robot/pelea")
    parser.add_argument("name", metavar="NAME", nargs="?", help="parameter (get, set, describe)")
    parser.add_argument("value", metavar="VALUE", nargs="?", help="new value (set), as YAML")
    parser.add_argument("--timeout", type=float, default=10.0, help="seconds to wait for the node")


def parse_value(text: str):
    """A command-line value as ROS takes it (``-p name:=value`` is YAML)."""
    import yaml

    try:
        return yaml.safe_load(text)
    except yaml.YAMLError as e:
        raise ValueError(f"{text!r} is not a value: {e}") from None


def run(args: argparse.Namespace) -> int:
    from rcl_interfaces.srv import (
        DescribeParameters,
        GetParameters,
        ListParameters,
        SetParameters,
    )
    from rclpy.parameter import Parameter, parameter_value_to_python

    from dsr_graph.ros.session import RosSession

    if args.action != "list" and not args.name:
        return error(f"param {args.action} needs NAME")
    if args.action == "set" and args.value is None:
        return error("param set needs VALUE")
    try:
        with RosSession(ros_args=args.ros_args) as ros:
            node = ros.node.resolve_topic_name(args.node)  # a relative name takes -r __ns:=

            def call(srv, suffix, request, what):
                client = ros.node.create_client(srv, f"{node}/{suffix}")
                return ros.call(client, request, args.timeout, what)

            if args.action == "list":
                found = call(ListParameters, "list_parameters", ListParameters.Request(), "list")
                print("\n".join(sorted(found.result.names)))
                return 0
            if args.action == "get":
                found = call(
                    GetParameters, "get_parameters", GetParameters.Request(names=[args.name]), "get"
                )
                if not found.values or found.values[0].type == 0:  # PARAMETER_NOT_SET
                    return error(f"{node} has no parameter {args.name}")
                print(json.dumps(parameter_value_to_python(found.values[0])))
                return 0
            if args.action == "describe":
                found = call(
                    DescribeParameters,
                    "describe_parameters",
                    DescribeParameters.Request(names=[args.name]),
                    "describe",
                )
                d = found.descriptors[0]
                print(f"{d.name}: {d.description}" + (" (read-only)" if d.read_only else ""))
                return 0
            value = parse_value(args.value)
            message = Parameter(args.name, value=value).to_parameter_msg()
            done = call(
                SetParameters, "set_parameters", SetParameters.Request(parameters=[message]), "set"
            )
            if not done.results[0].successful:
                return error(f"{node} refused {args.name}={args.value}: {done.results[0].reason}")
            print(f"{args.name} = {json.dumps(value)}")
            return 0
    except (DsrError, ValueError, TypeError) as e:
        return error(str(e))
