#!/usr/bin/env bash
# The README's test command: sets the workspace up if needed (idempotent), lints (ruff, pinned,
# ruff.toml), then runs the tests.
#   scripts/test.sh            the whole suite (what CI runs), on both cores: test/unit (no ROS,
#                              seconds) and test/system (processes, launches, docs, browser)
#   scripts/test.sh --quick    the five-minute loop: the unit tests and one system smoke test a
#                              package (pytest -m smoke), on both cores
# Extra arguments go to pytest (scripts/test.sh test/unit -x; scripts/test.sh --quick -x).
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
quick=""
if [ "${1:-}" = "--quick" ]; then
  quick=1
  shift
fi
"$root/scripts/setup.sh" --with-browser
# shellcheck disable=SC1091
source "$root/scripts/env.sh"
cd "$root"
echo "[test] ruff check . && ruff format --check ."
ruff check .
ruff format --check . > /dev/null || { ruff format --check . >&2; echo "[test] run: ruff format ." >&2; exit 1; }
mkdir -p test-results
# Fast DDS's shared-memory files of processes killed outright (an earlier run's crash tests) go
# as each worker takes its block of ROS domains and after each module (test/conftest.py).
# CI runs hypothesis derandomised so a run is reproducible; locally it explores new examples.
# Two workers (pytest-xdist), each with its own block of ROS domains (test/ros_processes.py)
# and temporary folders; a file's tests stay on one worker (they share its fixtures).
if [ -n "$quick" ]; then
  exec python -m pytest -n 2 --dist loadfile -m "unit or smoke" \
    --junitxml=test-results/junit-quick.xml "$@"
fi
if [ $# -gt 0 ]; then  # the caller's selection, on both workers
  exec python -m pytest -n 2 --dist loadfile --junitxml=test-results/junit.xml "$@"
fi
# The whole suite, on both workers.
exec python -m pytest -n 2 --dist loadfile --junitxml=test-results/junit.xml
