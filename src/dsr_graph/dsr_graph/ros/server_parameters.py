"""The DSR server's ROS parameters (their meaning: ros/server_node.py's docstring)."""

from __future__ import annotations

from dsr_graph.formats.default_paths import state_path
from dsr_graph.model.rt_history import DEFAULT_MAX_AGE, DEFAULT_MAX_COUNT
from dsr_graph.protocol.server_core import (
    DEFAULT_MAX_LEASE,
    DEFAULT_MAX_NODES,
    DEFAULT_MAX_OPS,
    DEFAULT_MAX_REQUEST_BYTES,
    DEFAULT_MAX_VALUE_BYTES,
)
from dsr_graph.ros.parameters import declare, float_param, param


def declare_server_parameters(node) -> None:
    declare(
        node,
        "world_file",
        "",
        "world file (ours or CORTEX) loaded when state_dir holds no state",
        read_only=True,
    )
    declare(
        node,
        "resume",
        False,
        "go on with the graph in state_dir even if it was made from another world_file",
        read_only=True,
    )
    declare(
        node,
        "vocabulary_file",
        "",
        "vocabulary file; empty for the built-in default",
        read_only=True,
    )
    declare(
        node,
        "state_dir",
        state_path("dsr", node.get_name()),
        "directory where the graph persists (empty: this default)",
        read_only=True,
    )
    declare(
        node,
        "compact_every",
        1000,
        "journaled deltas between snapshots",
        read_only=True,
        minimum=1,
    )
    declare(
        node,
        "commit_delay",
        0.0,
        "seconds a group commit waits for more changes before its fdatasync (fewer syncs "
        "under load, later verdicts)",
        read_only=True,
        minimum=0.0,
        maximum=10.0,
    )
    declare(
        node,
        "max_request_bytes",
        DEFAULT_MAX_REQUEST_BYTES,
        "requests of more UTF-8 bytes are rejected",
        read_only=True,
        minimum=1024,
    )
    declare(
        node,
        "max_ops",
        DEFAULT_MAX_OPS,
        "transactions of more operations are rejected",
        read_only=True,
        minimum=1,
    )
    declare(
        node,
        "max_nodes",
        DEFAULT_MAX_NODES,
        "a transaction that would grow the graph beyond this many nodes is rejected",
        read_only=True,
        minimum=1,
    )
    declare(
        node,
        "max_lease",
        DEFAULT_MAX_LEASE,
        "longest claim lease in seconds; a longer one is rejected",
        read_only=True,
        minimum=0.001,
    )
    declare(
        node,
        "max_value_bytes",
        DEFAULT_MAX_VALUE_BYTES,
        "a binary value (bytes, an image) of more bytes is rejected",
        read_only=True,
        minimum=1,
    )
    declare(
        node,
        "publish_poses",
        True,
        "publish geometry_msgs/PoseStamped per geometric node",
        read_only=True,
    )
    declare(
        node,
        "markers_period",
        1.0,
        "seconds between drawings of a changed graph on dsr/markers (0: none)",
        read_only=True,
        minimum=0.0,
    )
    declare(
        node,
        "heartbeat_period",
        1.0,
        "seconds between heartbeats and claim housekeeping",
        read_only=True,
        minimum=0.01,
    )
    declare(
        node,
        "agent_grace",
        3.0,
        "seconds a claim holder may be absent before its claims are freed",
        minimum=0.0,
    )
    declare(
        node,
        "rt_history_seconds",
        DEFAULT_MAX_AGE,
        "seconds of each RT edge's past transforms kept for dsr/get_transform's at",
        read_only=True,
        minimum=0.001,
    )
    declare(
        node,
        "rt_history_count",
        DEFAULT_MAX_COUNT,
        "past transforms kept per RT edge, at most",
        read_only=True,
        minimum=2,
    )
    declare(
        node,
        "policy_file",
        "",
        "YAML: who may write what, and claim priorities (empty: all may, all equal)",
        read_only=True,
    )


def limits(node) -> dict:
    """The request limits ServerCore takes."""
    return {
        "max_request_bytes": param(node, "max_request_bytes"),
        "max_ops": param(node, "max_ops"),
        "max_nodes": param(node, "max_nodes"),
        "max_lease": float_param(node, "max_lease"),
        "max_value_bytes": param(node, "max_value_bytes"),
    }
