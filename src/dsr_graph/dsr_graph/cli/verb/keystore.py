"""Make and fill a keystore for signed DSR traffic (our SROS2: docs in formats/keystore.py).

    dsr keystore init DIR [--server /dsr_server]   the folder, and the DSR server's key
    dsr keystore add DIR /node_name...              a key for each node (kept if it has one)
    dsr keystore list DIR                           the nodes that have a key

Run the suite with DSR_KEYSTORE=DIR (DSR_SECURITY=enforce by default then): every node signs
with its key, the server takes a request as a node's only when that node's key signed it, and
every replica keeps only what the server's key signed. Keys are files (0600, folders 0700)."""

from __future__ import annotations

import argparse

from dsr_graph.cli.api import error
from dsr_graph.exceptions import KeystoreError
from dsr_graph.formats.keystore import DEFAULT_SERVER, Keystore

HELP = "make a keystore (init), give nodes keys (add), list them (list)"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    actions = parser.add_subparsers(dest="action", metavar="ACTION", required=True)
    init = actions.add_parser("init", help="make a keystore with the DSR server's key")
    init.add_argument("dir", help="the keystore folder (made 0700)")
    init.add_argument(
        "--server",
        default=DEFAULT_SERVER,
        help=f"the DSR server's fully qualified node name (default {DEFAULT_SERVER})",
    )
    add = actions.add_parser("add", help="give nodes a key each")
    add.add_argument("dir", help="a keystore made by dsr keystore init")
    add.add_argument("names", nargs="+", metavar="NODE", help="fully qualified node names")
    show = actions.add_parser("list", help="the nodes that have a key")
    show.add_argument("dir")


def run(args: argparse.Namespace) -> int:
    try:
        if args.action == "init":
            keystore, made = Keystore.init(args.dir, args.server)
            verb = "made" if made else "already there, kept"
            print(f"keystore {keystore.root}: {verb}; server {keystore.server}")
            return 0
        keystore = Keystore.open(args.dir)
        if args.action == "list":
            for name in keystore.names():
                print(name + ("  (server)" if name == keystore.server else ""))
            return 0
        for name in args.names:
            made = keystore.add(name)
            print(f"{name}: {'key made' if made else 'has a key already (kept)'}")
        return 0
    except KeystoreError as e:
        return error(str(e))
