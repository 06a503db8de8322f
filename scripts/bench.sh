#!/usr/bin/env bash
# The DSR benchmarks, each figure next to its baseline measured in the same run (bench/run.py).
#   scripts/bench.sh [--quick] [--out FILE] [--only SECTION...]
# --quick runs every section with smaller sizes; the full run (more than an hour, most of it the
# speech section's five voices) adds 100k nodes, 4 agents, more samples, and every shipped Get Up
# & Go scenario through launch.sh quiet and with both cores busy. Each ratio is measured in
# interleaved rounds (bench/rounds.py). Report: bench-results/bench.json, and a table on stdout;
# exit 1 when a section failed (the others still ran).
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
"$root/scripts/setup.sh" >/dev/null
# shellcheck disable=SC1091
source "$root/scripts/env.sh"
exec python "$root/bench/run.py" "$@"
