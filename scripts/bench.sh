#!/usr/bin/env bash
# The DSR benchmarks, each figure next to its baseline measured in the same run (bench/run.py).
#   scripts/bench.sh [--quick] [--out FILE] [--only SECTION...]
# --quick takes about 4 minutes; the full run about 13 and adds 100k nodes,
# 4 agents, more samples, and every shipped Get Up & Go scenario through launch.sh quiet and
# with both cores busy. Report: bench-results/bench.json, and a table on stdout.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
"$root/scripts/setup.sh" >/dev/null
# shellcheck disable=SC1091
source "$root/scripts/env.sh"
exec python "$root/bench/run.py" "$@"
