"""Save the live graph of a running dsr_server to a file (our snapshot format, or CORTEX)."""

from __future__ import annotations

import argparse
import sys

from dsr_graph.cli.api import DsrError, error, with_snapshot

HELP = "save the live graph to FILE (a snapshot world file, or --format cortex)"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("file", metavar="FILE")
    parser.add_argument("--format", choices=("dsr", "cortex"), default="dsr")
    parser.add_argument(
        "--timeout", type=float, default=10.0, help="seconds to wait for the server"
    )


def run(args: argparse.Namespace) -> int:
    try:
        return with_snapshot(args.timeout, args.ros_args, lambda doc: save(doc, args))
    except (DsrError, OSError) as e:
        return error(str(e))


def save(doc: dict, args: argparse.Namespace) -> int:
    from dsr_graph.formats import dsr_json
    from dsr_graph.formats.world_files import world_document, write_json_atomically

    if args.format == "cortex":
        # trusted as a replica trusts it (the server's vocabulary may extend the default)
        graph, _ = dsr_json.snapshot_from_json(doc, trusted=True)
        doc = world_document(graph, "cortex")
    write_json_atomically(doc, args.file)
    print(f"saved the graph to {args.file} ({args.format})", file=sys.stderr)
    return 0
