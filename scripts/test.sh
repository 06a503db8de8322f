#!/usr/bin/env bash
# The README's test command: sets the workspace up if needed (idempotent), then runs the whole
# suite. Extra arguments go to pytest (e.g. scripts/test.sh -k kinematics -x).
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
"$root/scripts/setup.sh" --with-browser
# shellcheck disable=SC1091
source "$root/scripts/env.sh"
cd "$root"
mkdir -p test-results
# CI runs hypothesis derandomised so a run is reproducible; locally it explores new examples.
exec python -m pytest --junitxml=test-results/junit.xml "$@"
