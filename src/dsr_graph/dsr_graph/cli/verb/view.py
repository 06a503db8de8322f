"""Serve the live DSR viewer in the browser (the dsr_viewer node)."""

from __future__ import annotations

import argparse

HELP = "serve the live graph viewer on http://HOST:PORT/ (default 127.0.0.1:8080)"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--host", default="127.0.0.1")
    parser.add_argument("--port", type=int, default=8080)


def run(args: argparse.Namespace) -> int:
    from dsr_graph.ros.viewer_node import main

    return main(
        ["dsr_viewer", "--ros-args", "-p", f"host:={args.host}", "-p", f"port:={args.port}"]
    )
