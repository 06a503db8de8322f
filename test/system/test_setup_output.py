"""scripts/setup.sh speaks a line per step (its time and what it did) and keeps what the tools
print in its log; a failure names the step, shows the log's last lines and says what to do."""

import os
import re
import shutil
import subprocess
from pathlib import Path

REPO = Path(__file__).resolve().parents[2]
STEP = re.compile(r"^\[setup\] (.{30}) +\d+\.\ds  (.+)$")


def test_a_set_up_tree_says_a_line_per_step_and_nothing_else():
    run = subprocess.run(
        [str(REPO / "scripts" / "setup.sh"), "--with-browser"],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert run.returncode == 0, run.stderr
    lines = run.stdout.splitlines()
    *steps, ready = lines
    assert len(steps) == 9, lines
    for line in steps:
        match = STEP.match(line)
        assert match, line
        assert match[2].startswith(("already", "the system's", "skipped: ")), line
    assert ready.startswith("[setup] ready in ") and "setup.log" in ready, ready
    assert run.stderr == ""  # no terminal here: no progress line either


def test_a_failed_step_names_itself_shows_the_log_and_says_what_to_do(tmp_path):
    root = tmp_path / "workspace"
    (root / "scripts").mkdir(parents=True)
    shutil.copy(REPO / "scripts" / "setup.sh", root / "scripts" / "setup.sh")
    python = tmp_path / "python3.11"  # a Python that cannot make a venv
    python.write_text("#!/bin/sh\necho 'Error: ensurepip is not available' >&2\nexit 3\n")
    python.chmod(0o755)
    run = subprocess.run(
        [str(root / "scripts" / "setup.sh")],
        capture_output=True,
        text=True,
        timeout=60,
        env=dict(os.environ, DSR_PYTHON=str(python)),
    )
    assert run.returncode == 3
    assert run.stdout == ""
    log = root / ".setup-stamps" / "setup.log"
    assert f"[setup] FAILED: Python environment (exit 3). The last lines of {log}:" in run.stderr
    assert "    Error: ensurepip is not available" in run.stderr
    assert "[setup] what to do: check that" in run.stderr
    assert "ensurepip" in log.read_text()
