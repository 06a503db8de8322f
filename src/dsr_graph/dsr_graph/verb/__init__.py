"""Verbs of the ``dsr`` command line, one module each: HELP, add_arguments(parser), run(args) -> int.

Helpers shared by the verbs live here; modules whose names start with "_" are not verbs.
"""

from __future__ import annotations

import argparse
import sys

from ..exceptions import DsrError
from ..vocabulary import Vocabulary
from ..worldfile import LoadedWorld, read_world


def add_world_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("world", metavar="WORLD", help="world file: ours (format dsr-graph) or CORTEX, detected from the content")
    parser.add_argument("--vocabulary", metavar="FILE", default=None,
                        help="vocabulary file (default: the built-in one; a file may say \"extends\": \"default\")")


def load_world(args: argparse.Namespace) -> LoadedWorld:
    """Load WORLD; raises DsrError with a readable message when it cannot be read at all."""
    return read_world(args.world, Vocabulary.load(args.vocabulary))


def warn_violations(world: LoadedWorld, path: str) -> None:
    for v in world.violations:
        print(f"warning: left out: {v}", file=sys.stderr)
    if world.violations:
        print(f"warning: {path}: {len(world.violations)} element(s) left out; "
              f"`dsr validate {path}` lists them", file=sys.stderr)


def error(message: str) -> int:
    print(f"dsr: error: {message}", file=sys.stderr)
    return 1


__all__ = ["DsrError", "add_world_arguments", "load_world", "warn_violations", "error"]
