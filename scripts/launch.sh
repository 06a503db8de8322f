#!/usr/bin/env bash
# The README's main job. Sets the workspace up if needed, starts the DSR server on a world file
# (default: worlds/clarc_room.json), shows the graph, then follows every accepted change until
# Ctrl-C. Every process it starts is stopped when it exits, also on Ctrl-C.
#
#   scripts/launch.sh [--world FILE] [--state-dir DIR] [--fresh]
#
#   --world FILE     world to start from (ours or CORTEX); used when the state dir is empty
#   --state-dir DIR  where the server persists (default: var/dsr_state in this checkout)
#   --fresh          forget the stored state and start from the world again
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
world="$root/worlds/clarc_room.json"
state_dir="$root/var/dsr_state"
fresh=0
while [ $# -gt 0 ]; do
  case "$1" in
    --world) world=$(realpath "$2"); shift 2 ;;
    --state-dir) state_dir=$(realpath -m "$2"); shift 2 ;;
    --fresh) fresh=1; shift ;;
    -h|--help) sed -n '2,12p' "$0"; exit 0 ;;
    *) echo "launch.sh: unknown option $1 (see --help)" >&2; exit 2 ;;
  esac
done

"$root/scripts/setup.sh"
# shellcheck disable=SC1091
source "$root/scripts/env.sh"

[ "$fresh" = 1 ] && rm -rf "$state_dir"
mkdir -p "$state_dir" "$root/var/log"

pids=()
cleanup() {
  trap - EXIT INT TERM
  for pid in "${pids[@]}"; do kill -INT "$pid" 2>/dev/null || true; done
  for pid in "${pids[@]}"; do
    for _ in $(seq 50); do kill -0 "$pid" 2>/dev/null || break; sleep 0.1; done
    kill -KILL "$pid" 2>/dev/null || true
  done
}
trap cleanup EXIT
trap 'exit 130' INT TERM

echo "[launch] dsr_server on $world (state in $state_dir, log in var/log/dsr_server.log)"
dsr_server --ros-args -p world_file:="$world" -p state_dir:="$state_dir" \
  > "$root/var/log/dsr_server.log" 2>&1 &
pids+=($!)

dsr graph --timeout 20 || { echo "[launch] the server did not come up:" >&2; cat "$root/var/log/dsr_server.log" >&2; exit 1; }
echo "[launch] following accepted changes (dsr watch); in another shell: source scripts/env.sh && dsr apply FILE"
dsr watch --rejections &
pids+=($!)
wait "${pids[0]}"
