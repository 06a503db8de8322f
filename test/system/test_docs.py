"""The documentation site builds in strict mode (a broken link, a page outside the navigation or
a reference generator that fails is an error), with the four sections and a page for every
node; and every tutorial's commands run as written: each ```bash block of a tutorial, in order,
in one shell from the repository's folder, in a ROS domain of the test's own."""

import os
import re
import signal
import subprocess
from pathlib import Path

import pytest

from ros_processes import fresh_domain_id

REPO = Path(__file__).resolve().parents[2]
TUTORIALS = sorted((REPO / "docs" / "tutorials").glob("*.md"))
BASH = re.compile(r"^```bash\n(.*?)^```", re.S | re.M)


def test_the_site_builds_strictly_with_every_section_and_node(tmp_path):
    site = tmp_path / "site"
    env = dict(os.environ, NO_MKDOCS_2_WARNING="1", DISABLE_MKDOCS_2_WARNING="true")
    run = subprocess.run(
        ["mkdocs", "build", "--strict", "--site-dir", str(site)],
        cwd=REPO,
        capture_output=True,
        text=True,
        timeout=180,
        env=env,
    )
    assert run.returncode == 0, run.stderr[-4000:]
    assert "WARNING" not in run.stderr, run.stderr[-4000:]
    for section in ("tutorials", "how-to", "reference", "explanation"):
        assert any((site / section).glob("*.html")), section
    for package in ("dsr_graph", "clarc_agents", "clarc_sim"):
        for line in (REPO / "src" / package / "setup.py").read_text().splitlines():
            if "_node:main" in line:  # a page a node, with its --help as generated
                executable = line.split("=")[0].strip().strip('"')
                page = site / "reference" / "nodes" / f"{executable}.html"
                assert f"usage: {executable} [--help]" in page.read_text(), executable
    cli = (site / "reference" / "cli.html").read_text()
    assert "usage: dsr apply" in cli and "usage: clarc understand" in cli


def commands(tutorial: Path) -> str:
    return "".join(BASH.findall(tutorial.read_text()))


@pytest.mark.timeout(600)
@pytest.mark.parametrize("tutorial", TUTORIALS, ids=lambda p: p.stem)
def test_a_tutorials_commands_run_as_written(tutorial, tmp_path):
    script = commands(tutorial)
    assert script, f"{tutorial.name} has no bash block"
    env = dict(
        os.environ,
        TMPDIR=str(tmp_path),  # the tutorial's mktemp -d lands here, and goes with the test
        ROS_DOMAIN_ID=str(fresh_domain_id()),
        ROS_AUTOMATIC_DISCOVERY_RANGE="LOCALHOST",
    )
    # -e: the first command that fails fails the tutorial; -m: its background jobs are process
    # groups of their own, stopped below whatever happened
    shell = subprocess.Popen(
        ["bash", "-em", "-c", script],
        cwd=REPO,
        env=env,
        stdin=subprocess.DEVNULL,
        stdout=subprocess.PIPE,
        stderr=subprocess.STDOUT,
        text=True,
        start_new_session=True,
    )
    try:
        out, _ = shell.communicate(timeout=540)
    finally:
        try:
            os.killpg(shell.pid, signal.SIGKILL)
        except ProcessLookupError:
            pass
        _stop_what_it_left(tmp_path)
    assert shell.returncode == 0, f"{tutorial.name} failed:\n{out[-6000:]}"


def _stop_what_it_left(folder: Path) -> None:
    """Every process still running whose command line names the test's folder (a background
    job of the tutorial: with -m each is a process group of its own)."""
    for proc in Path("/proc").iterdir():
        if not proc.name.isdigit():
            continue
        try:
            cmdline = (proc / "cmdline").read_bytes().replace(b"\0", b" ").decode()
        except OSError:
            continue
        if str(folder) in cmdline:
            try:
                os.kill(int(proc.name), signal.SIGKILL)
            except ProcessLookupError:
                pass
