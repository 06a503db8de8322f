"""Who wrote what in a recording (``dsr record``): per agent, the node types it inserted or
deleted, the edge types it inserted, deleted or moved, and the attributes it set or removed, in
the terms of the server's policy (docs/FORMAT.md). With --policy, printed as a policy file that
allows exactly that, to review and ship as a ``policy_file``."""

from __future__ import annotations

import argparse

from dsr_graph.cli.api import error

HELP = "who wrote what in a recording, or a policy file drafted from it (--policy)"
SERVER = "dsr_server"  # the server's own deltas (claim housekeeping) need no entry


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("recording", metavar="FILE.mcap", nargs="+", help="recordings to read")
    parser.add_argument("--policy", action="store_true", help="print a policy file (YAML)")


def run(args: argparse.Namespace) -> int:
    import yaml

    from dsr_graph.exceptions import DsrError
    from dsr_graph.formats import dsr_json
    from dsr_graph.formats.mcap_recording import dsr_events
    from dsr_graph.model.policy import VERSION, observe_writes
    from dsr_graph.protocol.volatility import follows

    merged: dict[str, dict[str, set[str]]] = {}
    counts: dict[str, int] = {}
    try:
        for path in args.recording:
            graph, seq = None, 0
            for kind, _time, doc in dsr_events(path):
                if kind == "snapshot":
                    # as a replay reads it: the recorded server checked it against its own
                    # vocabulary, which may extend the default
                    graph, seq = dsr_json.snapshot_from_json(doc, trusted=True)
                elif graph is not None and follows(doc, seq):  # as replay_history reads it
                    observe_writes(merged, graph, doc)
                    seq = doc["seq"]
                    counts[doc.get("agent", "")] = counts.get(doc.get("agent", ""), 0) + 1
    except DsrError as e:
        return error(str(e))
    merged.pop(SERVER, None)
    if args.policy:
        agents = [
            {"name": agent, "priority": 0, **{k: sorted(v) for k, v in kinds.items() if v}}
            for agent, kinds in sorted(merged.items())
        ]
        print(f"# drafted by dsr writers from {', '.join(args.recording)}: review it, set the")
        print("# priorities, and decide what any other node may do (an entry named '*').")
        print(yaml.safe_dump({"version": VERSION, "agents": agents}, sort_keys=False), end="")
        return 0
    for agent, kinds in sorted(merged.items()):
        print(f"{agent}  ({counts.get(agent, 0)} transactions)")
        for kind, names in kinds.items():
            print(f"  {kind:<11} {', '.join(sorted(names)) or '-'}")
    return 0
