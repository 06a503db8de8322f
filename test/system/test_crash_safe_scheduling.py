"""A worker that dies (the watchdog ends a test stuck in C) fails its test and the run goes on to
the end: with pytest-xdist's own ``--dist loadfile`` the run below hangs, or stops at an internal
error having run 5 of its 13 tests (crash_safe_scheduling.py says why)."""

import re
import subprocess
import sys
import textwrap

from conftest import REPO

SUITE = {
    "test_a.py": """
        import time
        def test_a1(): time.sleep(0.3)
        def test_a2(): time.sleep(0.3)
        def test_a3(): time.sleep(0.3)
    """,
    # dies in the middle of a file: the tests after it still run, on a new worker
    "test_b.py": """
        import os
        def test_b1(): pass
        def test_b_dies(): os._exit(1)
        def test_b3(): pass
    """,
    # a file of one test that dies, and a file whose last test dies
    "test_c.py": "import os\ndef test_c_dies(): os._exit(3)\n",
    "test_d.py": """
        import os, time
        def test_d1(): time.sleep(0.2)
        def test_d_dies(): os._exit(1)
    """,
    **{f"test_{x}.py": f"def test_{x}1(): pass\n" for x in "efgh"},
}
DIED = {"test_b.py::test_b_dies", "test_c.py::test_c_dies", "test_d.py::test_d_dies"}


def test_a_dying_worker_fails_its_test_once_and_the_run_ends(tmp_path):
    for name, text in SUITE.items():
        (tmp_path / name).write_text(textwrap.dedent(text))
    (tmp_path / "conftest.py").write_text(
        f"import sys\nsys.path.insert(0, {str(REPO / 'test')!r})\n"
        "from crash_safe_scheduling import pytest_xdist_make_scheduler  # noqa: F401\n"
    )
    for workers in ("1", "2"):
        run = subprocess.run(
            [sys.executable, "-m", "pytest", "-p", "no:cacheprovider", "-n", workers]
            + ["--dist", "loadfile", "-q", "-o", "addopts="],
            cwd=tmp_path,
            capture_output=True,
            text=True,
            timeout=120,
        )
        out = run.stdout
        assert "3 failed, 10 passed" in out, out
        for nodeid in DIED:
            # reported once, as the worker's crash, and not run again (it would die again): one
            # failure section each (the summary's lines, cut to the terminal's width, say it too)
            section = rf"^worker 'gw\d+' crashed while running '{re.escape(nodeid)}'$"
            assert len(re.findall(section, out, re.MULTILINE)) == 1, out
        assert out.count("node down") == 3, out
