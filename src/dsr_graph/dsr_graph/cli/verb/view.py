"""Serve the DSR viewer in the browser: the live graph (the dsr_viewer node), or with --replay
a recording made by ``dsr record`` (no ROS needed), opened at its start with its timeline: scrub
through every change it holds."""

from __future__ import annotations

import argparse

from dsr_graph.cli.api import error

HELP = "serve the graph viewer on http://HOST:PORT/ (live, or --replay FILE.mcap)"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--host", default="127.0.0.1")
    parser.add_argument("--port", type=int, default=8080)
    parser.add_argument(
        "--token", default="", help="the page's access token (default: a new one, printed)"
    )
    parser.add_argument(
        "--replay",
        metavar="FILE.mcap",
        help="show a recording (dsr record) instead of the live DSR",
    )


def run(args: argparse.Namespace) -> int:
    if args.replay:
        return _replay(args)
    from dsr_graph.ros.viewer_node import main

    return main(
        [
            "dsr_viewer",
            *(args.ros_args or ["--ros-args"]),
            *("-p", f"host:={args.host}"),
            *("-p", f"port:={args.port}"),
            *("-p", f"token:={args.token}"),
        ]
    )


def _replay(args: argparse.Namespace) -> int:
    from pathlib import Path

    from aiohttp import web

    from dsr_graph.exceptions import RecordingError
    from dsr_graph.protocol.replay import replay_history
    from dsr_graph.web.events import Broadcaster
    from dsr_graph.web.guard import LOOPBACK, new_token
    from dsr_graph.web.viewer_app import make_app

    try:
        history = replay_history(args.replay)
    except RecordingError as e:
        return error(str(e))
    name = Path(args.replay).name
    token = args.token or new_token()
    print(
        f"replay of {name}: seq {history.first_seq} to {history.seq}; "
        f"DSR viewer on http://{args.host}:{args.port}/?token={token} (Ctrl-C to stop)",
        flush=True,
    )
    try:
        web.run_app(
            make_app(history, Broadcaster(), replay=name, token=token, hosts=LOOPBACK),
            host=args.host,
            port=args.port,
            print=None,
            access_log=None,
        )
    except OSError as e:
        return error(f"cannot serve on {args.host}:{args.port}: {e.strerror}")
    return 0
