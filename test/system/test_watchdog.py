"""conftest.py's watchdog: a test stuck inside C holding the GIL (where pytest-timeout's signal
never reaches it: a Fast DDS deadlock in a teardown) is ended with its Python and native stacks
written out, fails as its worker's crash, and the run goes on to the next test and ends."""

import os
import shutil
import subprocess
import sys
import textwrap

from conftest import REPO

STUCK = """
    import ctypes

    def test_stuck_in_c():
        # a deadlock in C that keeps the GIL: a default pthread mutex locked twice by its owner
        libc, mutex = ctypes.PyDLL(None), ctypes.create_string_buffer(64)
        libc.pthread_mutex_lock(mutex)
        libc.pthread_mutex_lock(mutex)

    def test_after():
        pass
"""
# the suite's own conftest, loaded under another name (this folder's is "conftest")
CONFTEST = f"""
    import importlib.util, sys
    sys.path.insert(0, {str(REPO / "test")!r})
    path = {str(REPO / "test" / "conftest.py")!r}
    spec = importlib.util.spec_from_file_location("dsr_conftest", path)
    dsr_conftest = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(dsr_conftest)
    globals().update({{k: v for k, v in vars(dsr_conftest).items() if k.startswith("pytest_")}})
"""


def test_a_test_stuck_in_c_is_ended_with_its_stacks_and_the_run_goes_on(tmp_path):
    (tmp_path / "test_stuck.py").write_text(textwrap.dedent(STUCK))
    (tmp_path / "conftest.py").write_text(textwrap.dedent(CONFTEST))
    run = subprocess.run(
        [sys.executable, "-m", "pytest", "-p", "no:cacheprovider", "-n", "1", "-rf"]
        + ["--dist", "loadfile", "-o", "addopts=", "-o", "timeout=2"],
        cwd=tmp_path,
        env={**os.environ, "DSR_TEST_WATCH_MARGIN": "9"},
        capture_output=True,
        text=True,
        timeout=120,
    )
    out = run.stdout + run.stderr
    assert "1 failed, 1 passed" in out, out
    assert "crashed while running 'test_stuck.py::test_stuck_in_c'" in out, out
    assert "Timeout (0:00:11)!" in out, out  # faulthandler's Python stacks, at limit + margin
    assert "line 8 in test_stuck_in_c" in out, out
    if shutil.which("gdb") is None:
        print("no gdb on this machine: the native stacks are not written")
        return
    native = out[out.index("--- native stacks (gdb) ---") :]
    assert "pthread_mutex_lock" in native and "Thread 1" in native, out
