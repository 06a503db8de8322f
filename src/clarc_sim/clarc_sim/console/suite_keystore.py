"""``clarc keystore DIR``: the DSR keystore of a CLARC run (dsr_graph/formats/keystore.py): made
if needed, with a key for every node of the suite that the launches start (kept when it has
one). scripts/launch.sh, scripts/two_hosts.sh and clarc.launch.py make theirs with it."""

from __future__ import annotations

import argparse
import sys

from dsr_graph.exceptions import KeystoreError
from dsr_graph.formats.keystore import DEFAULT_SERVER, Keystore

# every node of CLARC that signs (the DSR server's key is made by the keystore's init);
# /clarc_start is `clarc start` as the launches name it
SIGNERS = (
    "/tts",
    "/microphone",
    "/touchscreen",
    "/kinect",
    "/person",
    "/gait_analyser",
    "/camera",
    "/asr",
    "/speech",
    "/panel",
    "/pelea",
    "/patient",
    "/dsr_viewer",
    "/cgamed",
    "/clarc_monitor",
    "/dsr_recorder",
    "/clarc_start",
)


def suite_keystore(root: str, server: str = DEFAULT_SERVER) -> Keystore:
    keystore, _ = Keystore.init(root, server)
    for name in SIGNERS:
        keystore.add(name)
    return keystore


def add_parser(sub) -> None:
    p = sub.add_parser("keystore", help="the DSR keystore of a CLARC run: every node a key")
    p.add_argument("dir")
    p.add_argument("--server", default=DEFAULT_SERVER, help="the DSR server's node name")
    p.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    try:
        keystore = suite_keystore(args.dir, args.server)
    except KeystoreError as e:
        print(f"clarc keystore: {e}", file=sys.stderr)
        return 1
    print(f"keystore {keystore.root}: {len(keystore.names())} keys")
    return 0
