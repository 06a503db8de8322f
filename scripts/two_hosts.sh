#!/usr/bin/env bash
# CLARC on two "hosts", as the real robot ran (the Kinect and the microphone on a second PC):
# two network namespaces joined by a veth pair, with addresses that exist only inside them
# (nothing is sent anywhere else). Host A runs the DSR server, PELEA and CGAmed; host B the
# Kinect, Person, microphone, Speech, touch screen, Panel, TTS, the patient and the monitor.
# DDS discovers across the link as across a real network. Runs one whole Barthel test, prints
# it and its result, and exits 0 when the result was stored.
#
#   scripts/two_hosts.sh [--scenario FILE] [--partition SECONDS [--at SECONDS]] [--db PATH]
#                        [--scale X] [--timeout S] [--run-dir DIR] [--security MODE]
#
#   --partition S   cut the link (both ends down) for S seconds in the middle of the test
#   --at T          ... T seconds after Start (default 12: during the third item at the fast pace)
#   --scenario, --db, --scale, --timeout, --run-dir, --security: as scripts/launch.sh (the
#                   keystore, in the run's folder, is the one both hosts read, as a copy would be)
#
# Needs root (network namespaces). The namespaces, the link and every process are removed on
# every exit, Ctrl-C included.
set -euo pipefail
umask 077  # the runs' logs and states hold patients' data
if (( 0x$(awk '/^SigIgn/ {print $2}' /proc/$$/status) & 0x2 )); then
  exec env --default-signal=INT "$0" "$@"  # (see launch.sh: Ctrl-C must reach us)
fi
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
scenario="$root/scenarios/default.yaml"
db=""
scale=0.1
timeout=300
run=""
partition=0
at=12
security=enforce
while [ $# -gt 0 ]; do
  case "$1" in
    --scenario) scenario=$(realpath "$2"); shift 2 ;;
    --db) db=$(realpath -m "$2"); shift 2 ;;
    --scale) scale="$2"; shift 2 ;;
    --timeout) timeout="$2"; shift 2 ;;
    --run-dir) run=$(realpath -m "$2"); shift 2 ;;
    --partition) partition="$2"; shift 2 ;;
    --at) at="$2"; shift 2 ;;
    --security) security="$2"; shift 2 ;;
    -h|--help) awk 'NR > 1 && !/^#/ {exit} NR > 1 {sub(/^# ?/, ""); print}' "$0"; exit 0 ;;
    *) echo "two_hosts.sh: unknown option $1 (see --help)" >&2; exit 2 ;;
  esac
done
if [ "$(id -u)" != 0 ]; then
  echo "two_hosts.sh: needs root to make network namespaces (CI runs as root)" >&2
  exit 2
fi
command -v ip > /dev/null || { echo "two_hosts.sh: needs iproute2 (ip)" >&2; exit 2; }

"$root/scripts/setup.sh" | grep -v '^\[setup\] ready' || true
# shellcheck disable=SC1091
source "$root/scripts/env.sh"
patient=$(clarc scenario --patient "$scenario") || exit 2
[ -n "$run" ] || run="$root/var/runs/two-hosts-$(date +%Y%m%d-%H%M%S)-$$"
[ -n "$db" ] || db="$run/cgamed.sqlite"
mkdir -p "$run/log"
export DSR_SECURITY="$security"
if [ "$security" = off ]; then
  unset DSR_KEYSTORE
else
  clarc keystore "$run/keystore" > /dev/null || { echo "[two_hosts] no keystore, no run" >&2; exit 1; }
  export DSR_KEYSTORE="$run/keystore"
fi

# Names and addresses of our own: a /24 inside 10.213.0.0/16 picked by pid, only in the
# namespaces (no default route: nothing can leave them).
tag=$$
# Namespaces outlive a run that was SIGKILLed (no trap runs): remove those of our naming whose
# run is dead, so that they neither pile up nor look like this run's leftovers.
for ns in $(ip netns list | awk '$1 ~ /^dsr[AB][0-9]+$/ {print $1}'); do
  owner=${ns#dsr?}
  if ! grep -qs two_hosts.sh "/proc/$owner/cmdline"; then
    ip netns pids "$ns" 2>/dev/null | xargs -r kill -KILL 2>/dev/null || true
    if ip netns del "$ns" 2>/dev/null; then echo "[two_hosts] removed $ns, left by a run that died"; fi
  fi
done
nsA="dsrA$tag"; nsB="dsrB$tag"; vA="vdA$tag"; vB="vdB$tag"
net="10.213.$(( $$ % 250 ))"
source "$root/scripts/ros_domain.sh"  # as launch.sh: a domain no other run here holds
unset ROS_AUTOMATIC_DISCOVERY_RANGE  # SUBNET: discovery goes over the link
export FASTDDS_BUILTIN_TRANSPORTS=UDPv4  # the hosts share no memory on a real robot either
export ROS_STATIC_PEERS="$net.1;$net.2"  # discovery by unicast too, not multicast alone
# Across hosts, a participant is taken as gone after 10 s unheard (the suite's 2 s is for one
# machine, where it lets a restarted node be told from its killed self). A participant dropped
# and found again comes back without its node name in rmw_fastrtps's ROS graph (seen with
# these wheels): with --security off the DSR server would then refuse its requests; signed
# (the default), its requests prove who sent them without the ROS graph.
profile="$run/fastdds_profile.xml"
sed 's|<sec>2</sec></leaseDuration>|<sec>10</sec></leaseDuration>|' \
  "$root/src/dsr_graph/config/fastdds_profile.xml" > "$profile"
export FASTRTPS_DEFAULT_PROFILES_FILE="$profile"
export PYTHONUNBUFFERED=1

pids=()
cleanup() {
  local code=$?
  trap - EXIT INT TERM
  local pid
  for pid in "${pids[@]}"; do kill -INT "$pid" 2>/dev/null || true; done
  for pid in "${pids[@]}"; do
    for _ in $(seq 30); do kill -0 "$pid" 2>/dev/null || break; sleep 0.1; done
    kill -KILL "$pid" 2>/dev/null || true
  done
  ip netns pids "$nsA" 2>/dev/null | xargs -r kill -KILL 2>/dev/null || true
  ip netns pids "$nsB" 2>/dev/null | xargs -r kill -KILL 2>/dev/null || true
  ip netns del "$nsA" 2>/dev/null || true  # takes its end of the veth pair, and so the pair
  ip netns del "$nsB" 2>/dev/null || true
  exit "$code"
}
trap cleanup EXIT
trap 'exit 130' INT TERM

ip netns add "$nsA"
ip netns add "$nsB"
ip link add "$vA" type veth peer name "$vB"
ip link set "$vA" netns "$nsA"
ip link set "$vB" netns "$nsB"
ip -n "$nsA" addr add "$net.1/24" dev "$vA"
ip -n "$nsB" addr add "$net.2/24" dev "$vB"
for ns_dev in "$nsA:$vA" "$nsB:$vB"; do
  ns=${ns_dev%%:*}; dev=${ns_dev#*:}
  ip -n "$ns" link set lo up
  ip -n "$ns" link set "$dev" up
  ip -n "$ns" route add 224.0.0.0/4 dev "$dev"  # DDS discovery is multicast
done

on() {  # on HOST NAME COMMAND...: a node of the run on host A or B, logged to $run/log/NAME.log
  local ns=$nsA
  [ "$1" = B ] && ns=$nsB
  local name=$2
  shift 2
  ip netns exec "$ns" setpriv --pdeathsig KILL -- "$@" >> "$run/log/$name.log" 2>&1 &
  pids+=($!)
}

echo "[two_hosts] host A ($nsA, $net.1): dsr_server, pelea, cgamed; host B ($nsB, $net.2): kinect, person, microphone, speech, touchscreen, panel, tts, patient"
echo "[two_hosts] DSR security: $security${DSR_KEYSTORE:+ (keystore $DSR_KEYSTORE)}"
echo "[two_hosts] Barthel test for $patient, scenario $(basename "$scenario"), pace x$scale, ROS_DOMAIN_ID=$ROS_DOMAIN_ID; logs: $run/log"
scaled=(--ros-args -p time_scale:="$scale")
on A dsr_server dsr_server --ros-args -p world_file:="$root/worlds/clarc_room.json" \
  -p state_dir:="$run/dsr_state" -p policy_file:="$root/src/clarc_bringup/policy/clarc.yaml"
ip netns exec "$nsB" dsr graph --timeout 60 > "$run/log/initial_graph.txt" ||
  { echo "[two_hosts] host B does not reach the DSR server on host A:" >&2; cat "$run/log/dsr_server.log" >&2; exit 1; }
on B tts tts "${scaled[@]}" -p wav_dir:="$run/audio"
on B microphone microphone "${scaled[@]}"
on B touchscreen touchscreen
on B kinect kinect
on B person person "${scaled[@]}"
on B speech speech "${scaled[@]}"
on B panel panel "${scaled[@]}"
on B patient patient "${scaled[@]}" -p scenario:="$scenario"
on A pelea pelea "${scaled[@]}" -p outbox_dir:="$run/pelea_outbox"
on A cgamed cgamed --ros-args -p db:="$db" -p port:=0
since=$(date -u +%Y-%m-%dT%H:%M:%S+00:00)
ip netns exec "$nsA" clarc start "$patient" --timeout 60 --ros-args -r __node:=clarc_start \
  >> "$run/log/start.log" 2>&1 ||
  { echo "[two_hosts] could not press Start:" >&2; cat "$run/log/start.log" >&2; exit 1; }
started=$(date +%s.%N)

# The cut: both ends of the link down, so nothing passes either way (100% loss); then up
# again, with the multicast routes a link going down takes with it.
cut() {
  ip -n "$nsA" link set "$vA" down
  ip -n "$nsB" link set "$vB" down
}
mend() {
  ip -n "$nsA" link set "$vA" up
  ip -n "$nsB" link set "$vB" up
  ip -n "$nsA" route replace 224.0.0.0/4 dev "$vA"
  ip -n "$nsB" route replace 224.0.0.0/4 dev "$vB"
}
if [ "$partition" != 0 ]; then
  (
    sleep "$at"
    cut
    echo "[two_hosts] link cut at $(awk -v s="$started" -v n="$(date +%s.%N)" 'BEGIN {printf "%.1f", n - s}') s after Start, for $partition s"
    sleep "$partition"
    mend
    date +%s.%N > "$run/link_back"
    echo "[two_hosts] link back at $(awk -v s="$started" -v n="$(cat "$run/link_back")" 'BEGIN {printf "%.1f", n - s}') s after Start"
  ) &
  pids+=($!)
fi

# The monitor prints the test from the DSR, on host B: there it also shows the cut, as the DSR
# server's heartbeat going silent and coming back.
code=0
ip netns exec "$nsB" clarc_monitor --ros-args -p timeout:="$timeout.0" -p since:="$since" || code=$?
if [ "$code" -ne 0 ]; then
  echo "[two_hosts] the test did not complete (exit $code); see $run/log" >&2
  exit 1
fi
stored=$(clarc results --db "$db" --json | python -c 'import json, sys; print(len(json.load(sys.stdin)))')
if [ "$stored" -lt 1 ]; then
  echo "[two_hosts] no result stored in $db" >&2
  exit 1
fi
# How the two sides came back after the cut, from the logs' stamps: when the server heard each
# agent on host B again, and when each of them had resynchronised its replica.
if [ -f "$run/link_back" ]; then
  awk -v back="$(cat "$run/link_back")" '
    match($0, /\[[0-9]+\.[0-9]+\]/) {
      t = substr($0, RSTART + 1, RLENGTH - 2) - back
      if (t < 0) next
      if ($0 ~ /is back in reach after/) {
        split($0, w, "]: "); split(w[2], a, " ")
        printf "[two_hosts] %.1f s after the link came back: the server hears %s again\n", t, a[1]
      } else if ($0 ~ /resynchronised from a snapshot/ && !done[FILENAME]++) {
        n = split(FILENAME, f, "/"); sub(/\.log$/, "", f[n])
        printf "[two_hosts] %.1f s after the link came back: %s resynchronised\n", t, f[n]
      }
    }' "$run"/log/{dsr_server,speech,panel,person}.log | sort -t' ' -k2 -n || true
fi
echo "[two_hosts] test complete; stored in $db (clarc results --db $db)"
