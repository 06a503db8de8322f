"""Convert a world file between our format and CORTEX. Elements that break a rule are left out
and each is named on stderr (with --strict nothing is written and the exit code is 1)."""

from __future__ import annotations

import argparse
import sys

from dsr_graph.cli.api import DsrError, add_world_arguments, error, load_world, warn_violations
from dsr_graph.formats.world_files import FORMATS, write_world

HELP = "convert a world file to our format (dsr) or CORTEX"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    add_world_arguments(parser)
    parser.add_argument("out", metavar="OUT", help="file to write")
    parser.add_argument(
        "--format", choices=FORMATS, default="dsr", help="format of OUT (default: dsr)"
    )
    parser.add_argument(
        "--strict", action="store_true", help="write nothing if any element breaks a rule"
    )


def run(args: argparse.Namespace) -> int:
    try:
        world = load_world(args)
        if args.strict and world.violations:
            for v in world.violations:
                print(v, file=sys.stderr)
            return error(
                f"{args.world} has {len(world.violations)} violation(s); nothing written (--strict)"
            )
        warn_violations(world, args.world)
        write_world(world.graph, args.out, args.format)
    except (DsrError, OSError) as e:
        return error(str(e))
    print(
        f"wrote {args.out} ({args.format}: {len(world.graph)} nodes, "
        f"{world.graph.edge_count()} edges)",
        file=sys.stderr,
    )
    return 0
