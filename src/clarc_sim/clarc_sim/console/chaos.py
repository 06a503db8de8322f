"""``scripts/chaos.sh``: kill -9 processes of CLARC at random moments of a Barthel test, as a
user would with ``kill -9 <pid>`` during ``scripts/launch.sh``, and check that the test still
completes with exactly one stored result equal to an undisturbed run of the same scenario.

    scripts/chaos.sh [--seed N] [--runs K] [--kills M] [--scenario FILE] [--processes p,q,...]
                     [--against DB]

Each run kills ``--kills`` processes (default 1), each at a moment drawn by the seed between
``--earliest`` and ``--latest`` seconds after the test's first step; over the runs every process
is killed in turn (in an order shuffled by the seed). The seed is printed so that a failure can
be replayed. It prints one line per run and a table, one row per kill: process killed, moment,
time until the test went on (from the kill to the first step of the test printed after the
launch restarted the process), result equal yes/no. Exit 0 when every run's result equals the
undisturbed one, made first (or given: ``--against`` a results store holding one undisturbed
run of the same scenario).
"""

from __future__ import annotations

import argparse
import json
import os
import random
import re
import signal
import statistics
import subprocess
import sys
import tempfile
import threading
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Any

PROCESSES = ("pelea", "dsr_server", "speech", "panel", "person", "cgamed")
STEP = re.compile(r"^\[\s*([0-9.]+)s\] ")  # a monitor line: a step of the test


def comparable(result: dict[str, Any]) -> dict[str, Any]:
    """What a crash must not change: each item's points and how they were given, the total,
    the unanswered items, whether the clinician was called (attempts may differ: an item in
    progress is asked again)."""
    return {
        "items": [(i["item"], i["points"], i["via"]) for i in result["items"]],
        "total": result["total"],
        "unanswered": result["unanswered"],
        "clinician_called": result["clinician_called"],
    }


@dataclass
class Kill:
    process: str
    moment: float  # seconds after Start
    recovery: float | None = None  # seconds from the kill to the next step of the test


@dataclass
class Run:
    kills: list[Kill]  # in the order of their moments
    equal: bool = False
    note: str = ""


class Launch:
    """One ``scripts/launch.sh`` in the background, its output read line by line."""

    def __init__(self, root: Path, scenario: Path, work: Path, timeout: float):
        self.run_dir = work / "run"
        self.db = work / "results.sqlite"
        self.lines: list[tuple[float, str]] = []
        self.started_at: float | None = None  # when the monitor printed the test's first step
        self.proc = subprocess.Popen(
            [
                str(root / "scripts" / "launch.sh"),
                "--scenario",
                str(scenario),
                "--db",
                str(self.db),
                "--run-dir",
                str(self.run_dir),
                "--timeout",
                str(int(timeout)),
                "--viewer-port",
                "0",
                "--dashboard-port",
                "0",
            ],
            stdout=subprocess.PIPE,
            stderr=subprocess.STDOUT,
            text=True,
            start_new_session=True,
        )
        self._reader = threading.Thread(target=self._read, daemon=True)
        self._reader.start()

    def _read(self) -> None:
        for line in self.proc.stdout:
            now = time.monotonic()
            self.lines.append((now, line.rstrip("\n")))
            if self.started_at is None and STEP.match(line):  # the test is under way
                self.started_at = now

    def wait_started(self, timeout: float) -> bool:
        deadline = time.monotonic() + timeout
        while self.started_at is None and time.monotonic() < deadline and self.proc.poll() is None:
            time.sleep(0.05)
        return self.started_at is not None

    def kill9(self, process: str) -> float:
        pid = int((self.run_dir / "launch" / f"{process}.pid").read_text())
        os.kill(pid, signal.SIGKILL)
        return time.monotonic()

    def finish(self, timeout: float) -> int:
        try:
            code = self.proc.wait(timeout=timeout)
        except subprocess.TimeoutExpired:
            os.killpg(self.proc.pid, signal.SIGINT)
            code = self.proc.wait(timeout=30)
        self._reader.join(timeout=5)
        return code

    def went_on_after(self, killed: float, process: str) -> float | None:
        """Seconds from the kill to the first step of the test printed after the launch said it
        had restarted ``process``: the outage as the user sees it."""
        restarted = next(
            (
                at
                for at, line in self.lines
                if at > killed and line.startswith(f"[launch] {process} died")
            ),
            None,
        )
        if restarted is None:
            return None
        for at, line in self.lines:
            if at > restarted and STEP.match(line):
                return at - killed
        return None

    def results(self) -> list[dict[str, Any]]:
        done = subprocess.run(
            ["clarc", "results", "--db", str(self.db), "--json"],
            capture_output=True,
            text=True,
            timeout=60,
        )
        return json.loads(done.stdout) if done.returncode == 0 and done.stdout.strip() else []


def undisturbed(root: Path, scenario: Path, work: Path, timeout: float) -> dict[str, Any]:
    launch = Launch(root, scenario, work / "undisturbed", timeout)
    code = launch.finish(timeout + 60)
    stored = launch.results()
    if code != 0 or len(stored) != 1:
        tail = "\n".join(line for _, line in launch.lines[-15:])
        raise SystemExit(f"chaos: the undisturbed run failed (exit {code}):\n{tail}")
    return stored[0]


def stored_once(db: Path) -> dict[str, Any]:
    """The one result a results store holds (an undisturbed run made before)."""
    done = subprocess.run(
        ["clarc", "results", "--db", str(db), "--json"], capture_output=True, text=True, timeout=60
    )
    stored = json.loads(done.stdout) if done.returncode == 0 and done.stdout.strip() else []
    if len(stored) != 1:
        raise SystemExit(
            f"chaos: --against {db} must hold one stored result, it holds {len(stored)}"
        )
    return stored[0]


def chaos_run(
    root: Path, scenario: Path, work: Path, run: Run, expected: dict[str, Any], timeout: float
) -> Run:
    launch = Launch(root, scenario, work, timeout)
    if not launch.wait_started(90):
        launch.finish(5)
        run.note = "the test never started"
        return run
    killed: list[tuple[Kill, float]] = []
    for kill in run.kills:
        time.sleep(max(0.0, launch.started_at + kill.moment - time.monotonic()))
        if launch.proc.poll() is not None:
            break
        try:
            killed.append((kill, launch.kill9(kill.process)))
        except (OSError, ValueError) as e:  # e.g. killed again before the launch restarted it
            run.note = f"could not kill {kill.process}: {e}"
    code = launch.finish(timeout + 60)
    for kill, at in killed:
        kill.recovery = launch.went_on_after(at, kill.process)
    stored = launch.results()
    run.equal = code == 0 and len(stored) == 1 and comparable(stored[0]) == comparable(expected)
    if not run.equal and not run.note:
        run.note = f"exit {code}, {len(stored)} result(s)" + (
            f", got {comparable(stored[0])}" if len(stored) == 1 else ""
        )
        (work / "FAILED").write_text(run.note + "\n" + "\n".join(line for _, line in launch.lines))
    return run


def plan(
    seed: int, runs: int, kills: int, processes: list[str], earliest: float, latest: float
) -> list[Run]:
    """Processes taken in turn from a shuffled order (a run kills distinct ones while it can),
    moments drawn uniformly."""
    rng = random.Random(seed)
    order = list(processes)
    rng.shuffle(order)
    turn = (order[k % len(order)] for k in range(runs * kills))
    planned = []
    for _ in range(runs):
        chosen = [Kill(next(turn), round(rng.uniform(earliest, latest), 1)) for _ in range(kills)]
        planned.append(Run(sorted(chosen, key=lambda kill: kill.moment)))
    return planned


def table(runs: list[Run]) -> str:
    lines = [f"{'run':>3}  {'process':<11} {'moment':>7}  {'went on after':>13}  equal"]
    for k, r in enumerate(runs, 1):
        verdict = ("yes" if r.equal else "NO") + ("  " + r.note if r.note and not r.equal else "")
        for kill in r.kills:
            went_on = "-" if kill.recovery is None else f"{kill.recovery:.1f} s"
            lines.append(
                f"{k:>3}  {kill.process:<11} {kill.moment:>6.1f}s  {went_on:>13}  {verdict}"
            )
    by_process: dict[str, list[float]] = {}
    for kill in (kill for r in runs for kill in r.kills):
        if kill.recovery is not None:
            by_process.setdefault(kill.process, []).append(kill.recovery)
    for process, times in sorted(by_process.items()):
        lines.append(
            f"  {process:<11} went on after: median {statistics.median(times):.1f} s, "
            f"max {max(times):.1f} s ({len(times)} kills)"
        )
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="chaos.sh", description=__doc__.split("\n\n")[0])
    parser.add_argument("--seed", type=int, default=None, help="replay a run (printed at start)")
    parser.add_argument("--runs", type=int, default=6)
    parser.add_argument("--kills", type=int, default=1, help="processes killed in each run")
    parser.add_argument("--scenario", default=None, help="default: scenarios/default.yaml")
    parser.add_argument("--processes", default=",".join(PROCESSES))
    parser.add_argument("--earliest", type=float, default=1.0, help="seconds after Start")
    parser.add_argument("--latest", type=float, default=30.0, help="seconds after Start")
    parser.add_argument("--timeout", type=float, default=240.0, help="seconds for one test")
    parser.add_argument("--work", default=None, help="where runs keep their logs")
    parser.add_argument(
        "--against",
        default=None,
        help="a results store holding one undisturbed run of the same scenario (its result is "
        "the one to equal; default: a run made first)",
    )
    args = parser.parse_args(argv)
    root = Path(os.environ.get("DSR_WORKSPACE", Path(__file__).resolve().parents[4]))
    scenario = Path(args.scenario or root / "scenarios" / "default.yaml").resolve()
    seed = args.seed if args.seed is not None else random.SystemRandom().randrange(10**6)
    processes = [p for p in args.processes.split(",") if p]
    unknown = set(processes) - set(PROCESSES)
    if unknown:
        parser.error(f"unknown processes {sorted(unknown)}; choose among {', '.join(PROCESSES)}")
    if args.runs < 1 or args.kills < 1:
        parser.error("--runs and --kills must be at least 1")
    work = Path(args.work or tempfile.mkdtemp(prefix="clarc-chaos-"))
    print(
        f"[chaos] seed {seed} (replay: scripts/chaos.sh --seed {seed} --runs {args.runs} "
        f"--kills {args.kills}); "
        f"scenario {scenario.name}; logs in {work}",
        flush=True,
    )
    if args.against:
        expected = stored_once(Path(args.against))
    else:
        expected = undisturbed(root, scenario, work, args.timeout)
    print(
        f"[chaos] undisturbed: {expected['total']}/100, unanswered {expected['unanswered']}",
        flush=True,
    )
    runs = plan(seed, args.runs, args.kills, processes, args.earliest, args.latest)
    for k, run in enumerate(runs, 1):
        name = "-".join(kill.process for kill in run.kills)
        chaos_run(root, scenario, work / f"run{k:02d}-{name}", run, expected, args.timeout)
        kills = ", ".join(
            f"{kill.process} at {kill.moment:.1f} s (went on after "
            + ("-" if kill.recovery is None else f"{kill.recovery:.1f} s")
            + ")"
            for kill in run.kills
        )
        print(
            f"[chaos] run {k}/{len(runs)}: kill -9 {kills}: "
            f"result {'equal' if run.equal else 'DIFFERENT: ' + run.note}",
            flush=True,
        )
    print(table(runs))
    failed = sum(not r.equal for r in runs)
    print(f"[chaos] {len(runs) - failed} of {len(runs)} runs equal the undisturbed one")
    return 0 if failed == 0 else 1


if __name__ == "__main__":
    sys.exit(main())
