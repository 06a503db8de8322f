"""Check a world file against the graph rules and the vocabulary. Exit 0 when it is valid;
otherwise exit 1 and print one line per violation, naming the element and the rule."""

from __future__ import annotations

import argparse

from dsr_graph.cli.api import DsrError, add_world_arguments, error, load_world

HELP = "check a world file; one line per violation, exit 1 if any"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    add_world_arguments(parser)


def run(args: argparse.Namespace) -> int:
    try:
        world = load_world(args)
    except DsrError as e:
        return error(str(e))
    for violation in world.violations:
        print(violation)
    if world.violations:
        return 1
    graph = world.graph
    root = graph.rt_root()
    print(
        f"{args.world}: valid {world.format} world: {len(graph)} nodes, {graph.edge_count()} edges"
        + (f", RT tree rooted at {root.name!r}" if root else ", no RT edges")
    )
    return 0
