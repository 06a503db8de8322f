"""Declaring a node's parameters the one way: every parameter with a descriptor (what it is for,
its range where one applies, read-only when the node reads it only at start, required when the
node cannot run without it), and ``--help`` written from the same declarations."""

from __future__ import annotations

import sys
from dataclasses import dataclass
from typing import Any

from rcl_interfaces.msg import FloatingPointRange, IntegerRange, ParameterDescriptor
from rclpy.node import Node


def declare(
    node: Node,
    name: str,
    default: Any,
    description: str,
    *,
    read_only: bool = False,
    minimum: float | None = None,
    maximum: float | None = None,
    required: bool = False,
) -> None:
    """Declare ``name``. A float parameter also takes an integer on the command line
    (``-p time_scale:=1``); ``minimum``/``maximum`` bound numbers (rclpy refuses values outside);
    a ``required`` one (a string) must be given: ``check_required`` names it when it is not."""
    if required:  # said in the description, where --help and check_required read it
        description = f"{REQUIRED}{description}"
    descriptor = ParameterDescriptor(description=description, read_only=read_only)
    bounded = minimum is not None or maximum is not None
    if isinstance(default, float):
        descriptor.dynamic_typing = True
        if bounded:
            descriptor.floating_point_range = [
                FloatingPointRange(
                    from_value=float("-inf") if minimum is None else float(minimum),
                    to_value=float("inf") if maximum is None else float(maximum),
                    step=0.0,
                )
            ]
    elif isinstance(default, int) and not isinstance(default, bool) and bounded:
        descriptor.integer_range = [
            IntegerRange(
                from_value=-(2**63) if minimum is None else int(minimum),
                to_value=2**63 - 1 if maximum is None else int(maximum),
                step=1,
            )
        ]
    node.declare_parameter(name, default, descriptor)


REQUIRED = "required: "


def check_required(node: Node) -> None:
    """A required parameter left empty ends the node with a message naming it."""
    for name in node.list_parameters([], 0).names:
        description = node.describe_parameter(name).description
        if description.startswith(REQUIRED) and node.get_parameter(name).value in ("", None):
            description = description.removeprefix(REQUIRED)
            raise ValueError(
                f"parameter {name} is required ({description}): give it as "
                f"--ros-args -p {name}:=<value>"
            )


def param(node: Node, name: str) -> Any:
    return node.get_parameter(name).value


def float_param(node: Node, name: str) -> float:
    """A float parameter's value (also when it was given as an integer)."""
    return float(node.get_parameter(name).value)


def declare_time_scale(
    node: Node, description: str = "multiplies every time of the flow (0.1: ten times faster)"
) -> None:
    """``time_scale``: the session's pace, the same parameter on every CLARC node."""
    declare(node, "time_scale", 1.0, description, read_only=True, minimum=0.0)


def declare_setup_timeout(node: Node, default: float) -> None:
    """``setup_timeout``: how long ``setup()`` waits for the DSR server before failing."""
    declare(
        node,
        "setup_timeout",
        default,
        "seconds to wait for the DSR server",
        read_only=True,
        minimum=0.0,
    )


def declare_allowed_hosts(node: Node) -> None:
    """``allowed_hosts``: the Host names a web page of the node serves besides the loopback
    ones (web/guard.py)."""
    declare(
        node,
        "allowed_hosts",
        "",
        "Host names served besides 127.0.0.1, localhost and ::1 (comma-separated)",
        read_only=True,
    )


def allowed_hosts_of(node: Node) -> frozenset[str]:
    from dsr_graph.web.guard import allowed_hosts

    return allowed_hosts(param(node, "allowed_hosts").split(","))


@dataclass
class Declared:
    name: str
    default: Any
    descriptor: ParameterDescriptor


class ParameterList:
    """Stands for a node in ``declare_node_parameters`` to list the parameters without making one
    (no ROS context, no participant, no file touched)."""

    def __init__(self, node_name: str):
        self.node_name = node_name
        self.declared: list[Declared] = []

    def get_name(self) -> str:
        return self.node_name

    def declare_parameter(self, name: str, default: Any, descriptor: ParameterDescriptor) -> None:
        self.declared.append(Declared(name, default, descriptor))


def _limits(d: ParameterDescriptor) -> str:
    for bounds in (d.floating_point_range, d.integer_range):
        if bounds:
            low, high = bounds[0].from_value, bounds[0].to_value
            parts = [
                f">= {low:g}" if abs(low) < 2**62 else "",
                f"<= {high:g}" if abs(high) < 2**62 else "",
            ]
            return ", ".join(p for p in parts if p)
    return ""


def help_text(node_class, prog: str) -> str:
    """What ``<node> --help`` prints: what the node is, how to give parameters, and each
    parameter with its type, default, range and description."""
    listed = ParameterList(node_class.NAME)
    node_class.declare_node_parameters(listed)
    doc = (sys.modules[node_class.__module__].__doc__ or "").strip().split("\n\n")[0]
    lines = [
        f"usage: {prog} [--help] [--ros-args -p NAME:=VALUE ... -r __node:=NAME -r __ns:=/NS]",
        "",
        doc,
        "",
        f"node name: {node_class.NAME}",
        "parameters:" if listed.declared else "parameters: none",
    ]
    for p in listed.declared:
        d = p.descriptor
        notes = [type(p.default).__name__, f"default {p.default!r}"]
        if _limits(d):
            notes.append(_limits(d))
        if d.read_only:
            notes.append("read at start")
        lines.append(f"  {p.name} ({'; '.join(notes)})")
        lines.append(f"      {d.description}")
    return "\n".join(lines)
