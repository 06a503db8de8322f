"""``clarc``: the CLARC command line.

clarc results [--db PATH] [--json]   the stored tests (CGAmed's results store)
clarc scenario FILE [--patient|--test]  check a scenario file and show what the patient will do
clarc start PATIENT [--test TEST] [--patient-id N]
                                     press Start for a test (barthel, mmse, lawton,
                                     get_up_and_go), for a patient's record if given
clarc user add|list|disable|enable   the dashboard's users (console/user_cli.py)
clarc keystore DIR                   the DSR keystore of a run: every node of CLARC a key
clarc understand TEST ITEM "text"    how a text is understood and scored for an item
clarc hear FILE [--test T --item I]  what the recogniser hears in a recording (and its score)
"""

from __future__ import annotations

import argparse
import json
import os
import sys
from datetime import UTC, datetime

from clarc_agents import definitions
from clarc_agents.course import band_words
from clarc_agents.exceptions import ScenarioError
from clarc_sim.console import (
    hear_cli,
    skeleton_cli,
    suite_keystore,
    understand_cli,
    user_cli,
)
from clarc_sim.hospital.result_checks import tests_known, waiting_for_clinician
from clarc_sim.hospital.results_store import ResultsStore, default_db
from clarc_sim.patient.scenario import load
from dsr_graph.cli.api import split_ros_args
from dsr_graph.formats.private_files import set_private_umask


def now() -> str:
    return datetime.now(UTC).astimezone().isoformat(timespec="seconds")


def results(args: argparse.Namespace) -> int:
    store = ResultsStore(args.db)
    try:
        tests = store.tests()
    finally:
        store.close()
    if args.json:
        print(json.dumps(tests, indent=2))
        return 0
    if not tests:
        print(f"no tests stored in {args.db}")
    for t in tests:
        if t["test"] == "get_up_and_go":
            trials = f"({t['trials']} trial{'s' if t['trials'] != 1 else ''})"
            risk = "  [fall risk]" if t["fall_risk"] else ""
            if t["outcome"] == "unable":
                print(f"#{t['id']} {t['patient']}  {t['started']}  Get Up & Go unable to perform")
                print(f"    {trials}{risk}")
                for reason in t["void_reasons"]:
                    print(f"    {reason}")
                continue
            phases = ", ".join(f"{p} {s:.1f} s" for p, s in t["phases"].items())
            print(
                f"#{t['id']} {t['patient']}  {t['started']}  Get Up & Go {t['tug_seconds']:.1f} s"
                f" ({t['band']}){risk}"
            )
            print(f"    reaction {t['reaction_seconds']:.1f} s, {phases}  {trials}")
            continue
        flags = [
            f
            for f, on in (
                ("clinician called", t["clinician_called"]),
                ("person left", t["person_lost"]),
            )
            if on
        ]
        definition = definitions.load(t["test"])
        waiting = waiting_for_clinician(definition, t["items"])
        if waiting:
            flags.append(f"the clinician scores {', '.join(waiting)}")
        title = definition.title
        print(
            f"#{t['id']} {t['patient']}  {t['started']}  {title} {t['total']}/{t['max_total']}"
            f" ({t['band'] if t['band'] is not None else band_words(t)})"
            + (f"  [{', '.join(flags)}]" if flags else "")
        )
        for i in t["items"]:
            if i["points"] is None:
                got = "unanswered"
                if i["item"] in waiting:
                    got = "drawn, to score" if i["via"] else "not understood, to score"
            else:
                got = f"{i['points']:>2}/{definition.item(i['item']).max} by {i['via']}"
            print(f"    {i['item']:<17} {got}  ({i['attempts']} tries)")
    return 0


def scenario(args: argparse.Namespace) -> int:
    try:
        s = load(args.file)
    except ScenarioError as e:
        print(f"clarc: error: {e}", file=sys.stderr)
        return 1
    if args.patient:
        print(s.patient)
        return 0
    if args.test:
        print(s.test)
        return 0
    if args.language:
        print(s.language)
        return 0
    print(f"patient: {s.patient}")
    if s.test == "get_up_and_go":
        m = s.motion
        if m is None:
            print(f"test: get_up_and_go, the recording {s.recording} from {s.offset:g} s")
        else:
            print(f"test: get_up_and_go, {m.total:.1f} s from go until seated again")
            for phase in ("reaction", "rise", "walk_out", "turn", "walk_back", "sit"):
                print(f"  {phase:<10} {getattr(m, phase):.1f} s")
        extras = [f"noise {s.noise_mm:g} mm", f"{s.drop_rate:.0%} of frames lost"]
        if s.leave is not None:
            extras.append(f"walks out of view {s.leave:g} s after go")
        print(f"  ({', '.join(extras)})")
        return 0
    print(f"test: {s.test}" + (f", in {s.language}" if s.language != "en" else ""))
    for item in definitions.load(s.test).order:
        p = s.plan(item)
        what = "silent" if p.via == "silence" else f"{p.answer} points by {p.via}"
        extra = (f", first try {p.first}" if p.first else "") + (
            f", leaves for {p.leave} s" if p.leave is not None else ""
        )
        print(f"  {item:<17} {what}{extra}")
    return 0


def start(args: argparse.Namespace) -> int:
    """Press Start: a request for the patient on the DSR's test node, which PELEA takes as soon
    as it runs (a request made while PELEA is down or restarting waits there)."""
    from clarc_agents.test_node import request_start
    from dsr_graph.exceptions import DsrError

    shipped = definitions.languages(args.test) if args.test in definitions.tests() else ("en",)
    if args.language not in shipped:
        print(
            f"clarc: error: {args.test} is not shipped in {args.language!r} "
            f"(it is in: {', '.join(shipped)})",
            file=sys.stderr,
        )
        return 2
    from dsr_graph.ros.agent import DsrAgent
    from dsr_graph.ros.session import RosSession

    verdicts = []
    try:
        # named for the policy: clarc.yaml lets /clarc_start_* press Start and nothing else
        with RosSession(name=f"clarc_start_{os.getpid()}", ros_args=args.ros_args) as ros:
            agent = DsrAgent(describe=False)  # a one-shot tool
            agent.setup(ros.node, timeout_sec=args.timeout)
            ros.spin_until(lambda: agent.ready, args.timeout, "the DSR server")
            request = request_start(
                args.patient, now(), args.test, args.patient_id, agent.graph, args.language
            )
            agent.send(request, verdicts.append)
            ros.spin_until(lambda: bool(verdicts), args.timeout, "the DSR server's verdict")
            # told before the session closes: a DDS goodbye that hangs ends the tool with this
            if not verdicts[0].accepted:
                print(f"clarc: error: Start refused: {verdicts[0].error}", file=sys.stderr)
                ros.stuck_exit = 1
            else:
                in_language = f", in {args.language}" if args.language != "en" else ""
                print(f"Start pressed for {args.patient} ({args.test}{in_language})")
                ros.stuck_exit = 0
    except DsrError as e:
        print(f"clarc: error: {e}", file=sys.stderr)
        return 1
    return ros.stuck_exit


def build_parser() -> argparse.ArgumentParser:
    """The ``clarc`` command line (also the documentation's reference of it)."""
    parser = argparse.ArgumentParser(
        prog="clarc", description="CLARC: the clinical test robot's tools"
    )
    sub = parser.add_subparsers(dest="verb", required=True)
    p = sub.add_parser("results", help="the stored tests")
    p.add_argument("--db", default=default_db(), help=f"results store (default {default_db()})")
    p.add_argument("--json", action="store_true", help="a JSON list, one object per test")
    p.set_defaults(run=results)
    p = sub.add_parser("scenario", help="check a scenario file")
    p.add_argument("file")
    p.add_argument("--patient", action="store_true", help="print only the patient's name")
    p.add_argument("--test", action="store_true", help="print only the test it is for")
    p.add_argument("--language", action="store_true", help="print only the test's language")
    p.set_defaults(run=scenario)
    p = sub.add_parser("start", help="press Start for a patient")
    p.add_argument("patient")
    p.add_argument("--test", default="barthel", choices=tests_known(), help="which test (barthel)")
    p.add_argument("--patient-id", type=int, help="the patient's record in CGAmed's store")
    p.add_argument(
        "--language", default="en", help="what the test is asked in (en; es for the Barthel)"
    )
    p.add_argument("--timeout", type=float, default=20.0)
    p.set_defaults(run=start)
    user_cli.add_parser(sub)
    suite_keystore.add_parser(sub)
    skeleton_cli.add_parser(sub)
    understand_cli.add_parser(sub)
    hear_cli.add_parser(sub)
    return parser


def main(argv: list[str] | None = None) -> int:
    set_private_umask()  # the results store holds patients' data
    parser = build_parser()
    own, ros_args = split_ros_args(sys.argv[1:] if argv is None else argv)
    args = parser.parse_args(own)
    args.ros_args = ros_args
    return args.run(args)


if __name__ == "__main__":
    sys.exit(main())
