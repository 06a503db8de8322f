"""Print the transform between two geometric nodes of a world as JSON:
{"matrix": 4x4, "translation": [x, y, z], "quaternion_wxyz": [w, x, y, z]}.
The matrix maps coordinates expressed in frame TO into frame FROM, i.e. TO's pose seen from
FROM (like tf2's lookupTransform(target=FROM, source=TO))."""

from __future__ import annotations

import argparse
import json

from dsr_graph.cli.api import DsrError, add_world_arguments, error, load_world, warn_violations
from dsr_graph.model import rigid

HELP = "transform between two geometric nodes (TO's pose in FROM's frame) as JSON"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    add_world_arguments(parser)
    parser.add_argument(
        "frm", metavar="FROM", help="name (or numeric id) of the frame to express the pose in"
    )
    parser.add_argument(
        "to", metavar="TO", help="name (or numeric id) of the node whose pose is wanted"
    )


def _ref(graph, text: str):
    """A name if a node has it, else a numeric id."""
    if text in graph or not text.isdigit():
        return text
    return int(text)


def run(args: argparse.Namespace) -> int:
    try:
        world = load_world(args)
        warn_violations(world, args.world)
        graph = world.graph
        matrix = graph.transform(_ref(graph, args.frm), _ref(graph, args.to))
    except DsrError as e:
        return error(str(e))
    print(json.dumps(rigid.pose_json(matrix)))
    return 0
