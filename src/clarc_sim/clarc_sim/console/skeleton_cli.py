"""``clarc skeleton import --from mediapipe33|bvh|kinect25 IN OUT [--up AXIS] [--units U]
[--fps F]``: recorded movement as a CLARC skeleton recording (``patient/skeleton_import.py``),
which a Get Up & Go scenario plays with ``recording: OUT``."""

from __future__ import annotations

import argparse
import sys

import numpy as np

from clarc_sim.exceptions import SkeletonRecordingError
from clarc_sim.patient import skeleton_import, skeleton_recording


def add_parser(sub) -> None:
    p = sub.add_parser("skeleton", help="skeleton recordings (import)")
    actions = p.add_subparsers(dest="action", required=True)
    imp = actions.add_parser("import", help="recorded movement as a CLARC skeleton recording")
    imp.add_argument("--from", dest="kind", required=True, choices=skeleton_import.FORMATS)
    imp.add_argument("input")
    imp.add_argument("output")
    imp.add_argument(
        "--up", choices=tuple(skeleton_import.UP), help="the input's axis that points up"
    )
    imp.add_argument("--units", choices=tuple(skeleton_import.UNITS), help="the input's unit")
    imp.add_argument("--fps", type=float, help="frames per second, for an input without times")
    p.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    try:
        recording = skeleton_import.import_recording(
            args.kind, args.input, up=args.up, units=args.units, fps=args.fps
        )
        placed = skeleton_recording.placed(recording)  # checked now: a scenario can play it
        skeleton_recording.write(recording, args.output)
    except SkeletonRecordingError as e:
        print(f"clarc skeleton: {e}", file=sys.stderr)
        return 1
    except OSError as e:
        print(f"clarc skeleton: cannot write {args.output}: {e.strerror}", file=sys.stderr)
        return 1
    pelvis = placed.joint("pelvis")
    print(
        f"{args.output}: {len(recording.t)} frames, {recording.duration:.1f} s, joints "
        f"{', '.join(recording.joints)}; placed at the chair, the pelvis goes "
        f"{float(np.nanmax(pelvis[:, 0])):.1f} m along the walk"
    )
    return 0
