"""Helpers the verbs of ``dsr`` share: world-file arguments and loading, error output, and
fetching the live graph (the only helper that needs ROS, imported when called)."""

from __future__ import annotations

import argparse
import sys
from collections.abc import Callable

from dsr_graph.exceptions import DsrError
from dsr_graph.formats.world_files import LoadedWorld, read_world
from dsr_graph.model.vocabulary import Vocabulary


def add_world_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument(
        "world",
        metavar="WORLD",
        help="world file: ours (format dsr-graph) or CORTEX, detected from the content",
    )
    parser.add_argument(
        "--vocabulary",
        metavar="FILE",
        default=None,
        help='vocabulary file (default: the built-in one; a file may say "extends": "default")',
    )


def load_world(args: argparse.Namespace) -> LoadedWorld:
    """Load WORLD; raises DsrError with a readable message when it cannot be read at all."""
    return read_world(args.world, Vocabulary.load(args.vocabulary))


def warn_violations(world: LoadedWorld, path: str) -> None:
    for v in world.violations:
        print(f"warning: left out: {v}", file=sys.stderr)
    if world.violations:
        print(
            f"warning: {path}: {len(world.violations)} element(s) left out; "
            f"`dsr validate {path}` lists them",
            file=sys.stderr,
        )


def error(message: str) -> int:
    print(f"dsr: error: {message}", file=sys.stderr)
    return 1


def split_ros_args(argv: list[str]) -> tuple[list[str], list[str]]:
    """A command line split at ``--ros-args``: the tool's own arguments, and the ROS ones (with
    ``--ros-args`` first, as rclpy takes them; empty when there are none)."""
    if "--ros-args" not in argv:
        return list(argv), []
    k = argv.index("--ros-args")
    return list(argv[:k]), list(argv[k:])


def with_snapshot(timeout: float, ros_args: list[str] | None, use: Callable[[dict], int]) -> int:
    """``use(snapshot)``'s exit code, the snapshot fetched from the running server. ``use`` runs
    inside the ROS session, so that the tool has printed what it was asked for before the
    session's DDS goodbye, which can hang in Fast DDS (exit_timer.py): then the tool exits with
    that code all the same, never holding up its caller (launch.sh's ``dsr graph``)."""
    from dsr_graph.exceptions import SignatureRefused
    from dsr_graph.formats.safe_json import loads_object
    from dsr_graph.protocol.security import Security
    from dsr_graph.protocol.topic_names import GET_SNAPSHOT
    from dsr_graph.ros.session import RosSession
    from dsr_msgs.srv import GetSnapshot

    with RosSession(ros_args=ros_args) as ros:
        security = Security.from_environment(ros.node.get_fully_qualified_name())
        client = ros.node.create_client(GetSnapshot, GET_SNAPSHOT)
        text = ros.call(client, GetSnapshot.Request(), timeout, "the snapshot").snapshot_json
        opened, problem = security.from_server(GET_SNAPSHOT, text)
        if opened is None:
            raise SignatureRefused(f"the snapshot was not the DSR server's: {problem}")
        code = use(loads_object(opened, None))
        ros.stuck_exit = code  # exit_if_stuck flushes what use printed before it arms
        return code


def live_graph(doc: dict):
    """(graph, seq) of a snapshot ``with_snapshot`` gave; ``DsrError`` if it is not one."""
    from dsr_graph.exceptions import FormatError
    from dsr_graph.formats import dsr_json

    try:
        # trusted as every replica trusts it: the server checked each element against its own
        # vocabulary (which may extend the default), so only the structure is checked here
        return dsr_json.snapshot_from_json(doc, trusted=True)
    except FormatError as e:
        raise DsrError(f"the server's snapshot: {e}") from None


__all__ = [
    "DsrError",
    "add_world_arguments",
    "live_graph",
    "load_world",
    "warn_violations",
    "error",
    "with_snapshot",
    "split_ros_args",
]
