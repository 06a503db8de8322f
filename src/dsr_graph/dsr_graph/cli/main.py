"""``dsr``: the command line of the DSR. One module per verb in ``dsr_graph/cli/verb/`` (its
``NAME``, or the module's name); a new verb is a new file there, found at start (no central
switch). Shared helpers are in ``dsr_graph/cli/api/``. Offline verbs never import rclpy. The
online verbs take ROS arguments after ``--ros-args`` like any ROS node (``-r __ns:=/robot``,
remaps of the DSR's topics and services)."""

from __future__ import annotations

import argparse
import importlib
import pkgutil
import sys

from dsr_graph import __version__
from dsr_graph.cli import verb
from dsr_graph.cli.api import split_ros_args
from dsr_graph.formats.private_files import set_private_umask
from dsr_graph.ros import process_gc


def _verbs():
    for info in sorted(pkgutil.iter_modules(verb.__path__), key=lambda i: i.name):
        if not info.name.startswith("_"):
            module = importlib.import_module(f"{verb.__name__}.{info.name}")
            yield getattr(module, "NAME", info.name), module


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="dsr",
        description="Deep State Representation: inspect, validate and change DSR graphs.",
    )
    parser.add_argument("--version", action="version", version=f"dsr {__version__}")
    sub = parser.add_subparsers(dest="verb", metavar="VERB", required=True)
    for name, module in sorted(_verbs()):
        verb_parser = sub.add_parser(name, help=module.HELP, description=module.__doc__)
        module.add_arguments(verb_parser)
        verb_parser.set_defaults(run=module.run)
    return parser


def main(argv: list[str] | None = None) -> int:
    set_private_umask()  # recordings, saved graphs, keystores: the user's alone
    process_gc.use_dsr_policy()  # whole graphs read and written
    own, ros_args = split_ros_args(sys.argv[1:] if argv is None else argv)
    args = build_parser().parse_args(own)
    args.ros_args = ros_args
    try:
        return args.run(args)
    except KeyboardInterrupt:
        return 130
    except BrokenPipeError:  # `dsr ... | head`
        return 0


if __name__ == "__main__":
    sys.exit(main())
