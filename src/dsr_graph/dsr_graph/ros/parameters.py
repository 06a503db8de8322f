"""Declaring a node's parameters the one way: every parameter with a descriptor (what it is for,
its range where one applies, read-only when the node reads it only at start)."""

from __future__ import annotations

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
) -> None:
    """Declare ``name``. A float parameter also takes an integer on the command line
    (``-p time_scale:=1``); ``minimum``/``maximum`` bound numbers (rclpy refuses values outside)."""
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


def param(node: Node, name: str) -> Any:
    return node.get_parameter(name).value


def float_param(node: Node, name: str) -> float:
    """A float parameter's value (also when it was given as an integer)."""
    return float(node.get_parameter(name).value)


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
