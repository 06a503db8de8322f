"""Record the session to an MCAP file (ROS 2 profile, CDR): the DSR's graph at the start and
every accepted delta, /tf, /tf_static, dsr/markers, the poses and every other topic (the CLARC
device topics), until Ctrl-C or --duration. Open it in Foxglove, with ``ros2 bag`` or with
``dsr view --replay FILE.mcap``. Runs the dsr_recorder node (its parameters: dsr_recorder
--help)."""

from __future__ import annotations

import argparse

HELP = "record the DSR and the ROS topics to an MCAP file (Foxglove, ros2 bag, dsr view --replay)"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("output", metavar="FILE.mcap", help="the file to write (never overwritten)")
    parser.add_argument(
        "--duration", type=float, default=0.0, help="stop after S seconds (default: at Ctrl-C)"
    )
    parser.add_argument(
        "--include", default=".*", metavar="REGEX", help="record only the topics it finds"
    )
    parser.add_argument(
        "--exclude", default="", metavar="REGEX", help="leave out the topics it finds"
    )
    parser.add_argument(
        "--timeout", type=float, default=20.0, help="seconds to wait for the DSR server"
    )


def run(args: argparse.Namespace) -> int:
    from dsr_graph.ros.recorder_node import main

    ros_args = args.ros_args or ["--ros-args"]
    return main(
        [
            "dsr_recorder",
            *ros_args,
            *("-p", f"output:={args.output}"),
            *("-p", f"duration:={float(args.duration)}"),
            *("-p", f"include:={_yaml_text(args.include)}"),
            *("-p", f"exclude:={_yaml_text(args.exclude)}"),
            *("-p", f"setup_timeout:={float(args.timeout)}"),
        ]
    )


def _yaml_text(text: str) -> str:
    """A string as a ROS parameter value (parsed as YAML): quoted, so a regex stays a string."""
    return "'" + text.replace("'", "''") + "'"
