"""``clarc user``: the clinician's dashboard's accounts, in the results store (``--db`` chooses
it as ``clarc results --db`` does).

    clarc user add NAME --role technician|clinician|admin [--db PATH]
    clarc user list [--db PATH]
    clarc user disable NAME [--db PATH]    (enable NAME undoes it)

The password is read from the terminal (asked twice), or, when stdin is not a terminal, as its
first two lines (the same password twice), so a script can make the first user. Each change is
in the store's audit trail, made by ``clarc user (uid N)``."""

from __future__ import annotations

import argparse
import getpass
import os
import sys

from clarc_sim.exceptions import AccountError
from clarc_sim.hospital import accounts
from clarc_sim.hospital.accounts_table import ROLES
from clarc_sim.hospital.results_store import ResultsStore, default_db


def add_parser(sub) -> None:
    p = sub.add_parser("user", help="the dashboard's users (add, list, disable, enable)")
    actions = p.add_subparsers(dest="action", required=True)
    add = actions.add_parser("add", help="a new user; the password is asked twice")
    add.add_argument("name")
    add.add_argument("--role", required=True, choices=ROLES)
    listed = actions.add_parser("list", help="the users, their roles, who is disabled")
    disable = actions.add_parser("disable", help="the user can no longer log in")
    disable.add_argument("name")
    enable = actions.add_parser("enable", help="a disabled user can log in again")
    enable.add_argument("name")
    for action in (add, listed, disable, enable):
        action.add_argument(
            "--db", default=default_db(), help=f"results store (default {default_db()})"
        )
    p.set_defaults(run=run)


def read_password() -> str:
    """Twice, from the terminal or from stdin's first two lines; ``AccountError`` if they differ."""
    if sys.stdin.isatty():
        first, second = getpass.getpass("Password: "), getpass.getpass("Password again: ")
    else:
        first, second = sys.stdin.readline().rstrip("\n"), sys.stdin.readline().rstrip("\n")
    if first != second:
        raise AccountError("the two passwords differ")
    return accounts.check_password(first)


def run(args: argparse.Namespace) -> int:
    store = ResultsStore(args.db)
    me = f"clarc user (uid {os.getuid()})"
    try:
        if args.action == "list":
            for user in store.users():
                state = "  (disabled)" if user["disabled"] else ""
                print(f"{user['name']}\t{user['role']}\tsince {user['created']}{state}")
            return 0
        if args.action == "add":
            made = store.add_user(args.name, args.role, accounts.hash_password(read_password()))
            store.audit(me, "added a user", None, f"{made['name']} ({made['role']})")
            print(f"user {made['name']} ({made['role']}) added to {args.db}")
            return 0
        disable = args.action == "disable"
        store.set_disabled(args.name, disable)
        store.audit(me, "disabled a user" if disable else "enabled a user", None, args.name)
        print(f"user {args.name} {'disabled' if disable else 'enabled'}")
        return 0
    except AccountError as e:
        print(f"clarc user: {e}", file=sys.stderr)
        return 1
    finally:
        store.close()
