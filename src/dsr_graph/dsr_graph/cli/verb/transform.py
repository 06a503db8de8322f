"""Print the transform between two geometric nodes as JSON:
{"matrix": 4x4, "translation": [x, y, z], "quaternion_wxyz": [w, x, y, z]}.
The matrix maps coordinates expressed in frame TO into frame FROM, i.e. TO's pose seen from
FROM (like tf2's lookupTransform(target=FROM, source=TO)). From a world file (WORLD FROM TO), or
from the running dsr_server (--live FROM TO), now or, with --at, at a past time from the
server's RT history (interpolated between the two nearest values)."""

from __future__ import annotations

import argparse
import json
import time

from dsr_graph.cli.api import DsrError, error, warn_violations
from dsr_graph.formats import safe_json
from dsr_graph.formats.world_files import read_world
from dsr_graph.model import rigid
from dsr_graph.model.vocabulary import Vocabulary

HELP = "transform between two geometric nodes (TO's pose in FROM's frame) as JSON"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument(
        "names",
        nargs="+",
        metavar="ARG",
        help="WORLD FROM TO (a world file: ours or CORTEX), or FROM TO with --live; FROM: the "
        "frame to express the pose in, TO: the node whose pose is wanted (names, or numeric "
        "ids in a file)",
    )
    parser.add_argument(
        "--live", action="store_true", help="ask the running dsr_server (dsr/get_transform)"
    )
    parser.add_argument(
        "--at",
        type=float,
        default=None,
        metavar="T",
        help="the pose at time T, seconds since the epoch, or T < 0: -T seconds ago (with "
        "--live: a world file holds no history)",
    )
    parser.add_argument(
        "--vocabulary", metavar="FILE", default=None, help="vocabulary file (with a world file)"
    )
    parser.add_argument(
        "--timeout", type=float, default=10.0, help="seconds to wait for the server (--live)"
    )


def _ref(graph, text: str):
    """A name if a node has it, else a numeric id."""
    if text in graph or not text.isdigit():
        return text
    return int(text)


def run(args: argparse.Namespace) -> int:
    wanted = 2 if args.live else 3
    if len(args.names) != wanted:
        shape = "FROM TO" if args.live else "WORLD FROM TO (or --live FROM TO)"
        return error(f"give {shape}, got {len(args.names)} argument(s)")
    if args.at is not None and not args.live:
        return error("--at needs --live: a world file holds no RT history")
    try:
        if args.live:
            at = 0.0 if args.at is None else args.at if args.at >= 0 else time.time() + args.at
            pose = _live(args, *args.names, at)
        else:
            world = read_world(args.names[0], Vocabulary.load(args.vocabulary))
            warn_violations(world, args.names[0])
            graph = world.graph
            frm, to = (_ref(graph, name) for name in args.names[1:])
            pose = rigid.pose_json(graph.transform(frm, to))
    except DsrError as e:
        return error(str(e))
    print(json.dumps(pose))
    return 0


def _live(args: argparse.Namespace, frm: str, to: str, at: float) -> dict:
    from dsr_graph.protocol.topic_names import GET_TRANSFORM
    from dsr_graph.ros.session import RosSession
    from dsr_msgs.srv import GetTransform

    with RosSession(ros_args=args.ros_args) as ros:
        client = ros.node.create_client(GetTransform, GET_TRANSFORM)
        request = GetTransform.Request(from_node=frm, to_node=to, at=at)
        answer = ros.call(client, request, args.timeout, "the transform")
    if not answer.found:
        raise DsrError(answer.error)
    return safe_json.loads(answer.pose_json, None)
