#!/usr/bin/env bash
# Chaos test of CLARC, as a user would do it: kill -9 processes (pelea, dsr_server, speech,
# panel, person, cgamed) at random moments of a Barthel test run by scripts/launch.sh, and check
# that the test completes with exactly one stored result equal to an undisturbed run.
#
#   scripts/chaos.sh [--seed N] [--runs K] [--kills M] [--scenario FILE] [--processes p,q,...]
#
# The seed is printed so that a failure can be replayed; the table at the end gives, per kill,
# the process killed, the moment, the time until the test went on, and whether the run's result
# was equal. Exit 0 when every run's result is equal. Logs of each run: the folder it prints.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
"$root/scripts/setup.sh" | grep -v '^\[setup\] ready' || true
# shellcheck disable=SC1091
source "$root/scripts/env.sh"
exec python -m clarc_sim.console.chaos "$@"
