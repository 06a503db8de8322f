#!/usr/bin/env bash
# The README's main job: CLARC runs one whole Barthel test with a simulated patient.
#
# Sets the workspace up if needed, then starts, each as its own process: the DSR server (on
# worlds/clarc_room.json, fresh state per run), the four agents (PELEA, Speech, Panel, Person),
# the stand-ins (TTS, microphone, touch screen, Kinect, the patient following a scenario, the
# CGAmed hospital server) and a monitor that prints one line per step and the result. Every node
# is supervised, as launch_ros does with respawn=True: a node that dies is restarted after a
# short delay ("[launch] <node> died (<signal or exit code>), restarted (<n>)"); more than 5
# deaths of one node within a minute stop the run (exit 1). Stops every process it started when
# the test ends, on Ctrl-C, or on any error; exits 0 when the test completed and its result was
# stored.
#
#   scripts/launch.sh [--scenario FILE] [--db PATH] [--realtime] [--scale X] [--no-respawn]
#
#   --scenario FILE  what the patient does (default scenarios/default.yaml)
#   --db PATH        CGAmed's results store (default ~/.local/share/clarc/cgamed.sqlite)
#   --realtime       paced like a real session (10-15 minutes); the default is fast (~30 s)
#   --scale X        any other pace: every time multiplied by X (fast is 0.1)
#   --timeout S      give up after S seconds (default 600)
#   --run-dir DIR    where this run's logs, audio and DSR state go (default var/runs/<time>)
#   --wait-start     do not press Start: the clinician presses it on the dashboard
#   --viewer-port N  the DSR viewer's port (default 8080); --dashboard-port N (default 8081)
#   --no-respawn     a node that dies ends the launch at once (exit 1) instead of restarting
#   --record FILE    record the run to an MCAP file (dsr record: the DSR from its first state,
#                    /tf, markers, every device topic); open it with dsr view --replay FILE or
#                    in Foxglove. The recorder starts before the robot and stops after it.
#   --keystore DIR   sign the DSR's traffic with this keystore (dsr keystore init/add; every
#                    node of the suite needs its key); default: a new one in the run's folder
#   --security MODE  enforce (default), permissive or off (DSR_SECURITY; docs/explanation/who-may-do-what.md)
#   --viewer-token T the DSR viewer's access token (default: a new one, printed)
#   --camera HZ      the Kinect's colour and depth cameras on (640x480, HZ images a second of
#                    wall time), written into the DSR's kinect node by the camera agent
#   --audio          the whole loop with sound: the robot speaks (espeak-ng), the patient
#                    answers aloud in the scenario's voice and room noise, the asr node
#                    recognises the microphone's stream (Whisper); at real time (audio
#                    cannot be sped up) unless --scale says otherwise. The microphone's stream
#                    goes to <run-dir>/audio/microphone.wav, what the robot said beside it,
#                    and a clip of each answer heard to <run-dir>/audio/clips/.
#   --voice-rate WPM the robot's speaking rate with --audio (default 150 words a minute)
#
# While it runs: the DSR viewer on http://127.0.0.1:8080/ and the clinician's dashboard on
# http://127.0.0.1:8081/.
#
# See the results later: clarc results [--db PATH].
set -euo pipefail
umask 077  # logs, the run's DSR state, recordings and the results store hold patients' data
# Started as a background job of a non-interactive shell, this script inherits SIGINT ignored,
# and bash cannot trap a signal ignored at entry: restore its default so that Ctrl-C (SIGINT)
# always stops the run cleanly.
if (( 0x$(awk '/^SigIgn/ {print $2}' /proc/$$/status) & 0x2 )); then
  exec env --default-signal=INT "$0" "$@"
fi
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
scenario="$root/scenarios/default.yaml"
db=""
scale=0.1
timeout=600
run=""
wait_start=0
viewer_port=8080
dashboard_port=8081
respawn=1
record=""
keystore=""
security=enforce
viewer_token=""
camera_hz=0
audio=false
voice_rate=150
scale_given=0
respawn_delay=${CLARC_RESPAWN_DELAY:-0.5}  # seconds before a dead node is started again
max_deaths=5  # per node within a minute; one more stops the run
while [ $# -gt 0 ]; do
  case "$1" in
    --scenario) scenario=$(realpath "$2"); shift 2 ;;
    --db) db=$(realpath -m "$2"); shift 2 ;;
    --realtime) scale=1.0; scale_given=1; shift ;;
    --scale) scale="$2"; scale_given=1; shift 2 ;;
    --audio) audio=true; shift ;;
    --voice-rate) voice_rate="$2"; shift 2 ;;
    --timeout) timeout="$2"; shift 2 ;;
    --run-dir) run=$(realpath -m "$2"); shift 2 ;;
    --wait-start) wait_start=1; shift ;;
    --viewer-port) viewer_port="$2"; shift 2 ;;
    --dashboard-port) dashboard_port="$2"; shift 2 ;;
    --no-respawn) respawn=0; shift ;;
    --record) record=$(realpath -m "$2"); shift 2 ;;
    --keystore) keystore=$(realpath -m "$2"); shift 2 ;;
    --security) security="$2"; shift 2 ;;
    --viewer-token) viewer_token="$2"; shift 2 ;;
    --camera) camera_hz="$2"; shift 2 ;;
    -h|--help) awk 'NR > 1 && !/^#/ {exit} NR > 1 {sub(/^# ?/, ""); print}' "$0"; exit 0 ;;
    *) echo "launch.sh: unknown option $1 (see --help)" >&2; exit 2 ;;
  esac
done

"$root/scripts/setup.sh" | grep -v '^\[setup\] ready' || true
if [ "$audio" = true ]; then
  command -v espeak-ng >/dev/null 2>&1 ||
    { echo "launch.sh: --audio needs espeak-ng (apt-get install espeak-ng)" >&2; exit 2; }
  [ "$scale_given" = 1 ] || scale=1.0  # sound plays at its own pace
fi
# shellcheck disable=SC1091
source "$root/scripts/env.sh"

# A bad scenario is refused before anything starts, with the line that is wrong.
patient=$(clarc scenario --patient "$scenario") || exit 2
test_kind=$(clarc scenario --test "$scenario") || exit 2
test_language=$(clarc scenario --language "$scenario") || exit 2
in_language=""
[ "$test_language" = en ] || in_language=" (in $test_language)"
case "$test_kind" in
  get_up_and_go) test_name="Get Up & Go" ;; mmse) test_name="Mini-Mental" ;;
  lawton) test_name="Lawton" ;; *) test_name="Barthel" ;;
esac
[ -n "$db" ] || db=$(python -c 'from clarc_sim.hospital.results_store import default_db; print(default_db())')

# Results CGAmed has not acknowledged wait in an outbox of their own store, sent again next time.
outbox="$root/var/pelea_outbox/$(printf '%s' "$db" | sha1sum | cut -c1-12)"
[ -n "$run" ] || run="$root/var/runs/$(date +%Y%m%d-%H%M%S)-$$"
mkdir -p "$run/log"
# Our own ROS domain unless the caller chose one, so that no other run on this machine meets it.
source "$root/scripts/ros_domain.sh"
export ROS_AUTOMATIC_DISCOVERY_RANGE="${ROS_AUTOMATIC_DISCOVERY_RANGE:-LOCALHOST}"
# Fast DDS's shared-memory files of processes killed outright (a robot that lost power): a stale
# port can hang a new node at start. Those of living processes, and other domains' ports, stay.
dsr shm-clean --domain "$ROS_DOMAIN_ID" 2> /dev/null || true

case "$security" in enforce|permissive|off) ;;
  *) echo "launch.sh: --security is enforce, permissive or off, not $security" >&2; exit 2 ;;
esac
# Signed DSR traffic: a keystore with a key for every node of the run (kept if given and there).
export DSR_SECURITY="$security"
if [ "$security" = off ]; then
  unset DSR_KEYSTORE
else
  [ -n "$keystore" ] || keystore="$run/keystore"
  clarc keystore "$keystore" > /dev/null || { echo "[launch] no keystore, no run" >&2; exit 1; }
  export DSR_KEYSTORE="$keystore"
fi

# Each node runs under a supervisor (a background subshell of this script) that restarts it
# when it dies. $sup holds each node's current pid (<node>.pid: scripts/chaos.sh kills by it) and
# the markers the supervisors and this script share.
sup="$run/launch"
mkdir -p "$sup"
supervisors=()
nodes=()

exit_reason() {  # exit_reason CODE: "SIGKILL", or "exit code 3"
  local sig
  if [ "$1" -gt 128 ] && sig=$(kill -l $(($1 - 128)) 2>/dev/null); then
    echo "SIG$sig"
  else
    echo "exit code $1"
  fi
}

supervise() {  # supervise NAME COMMAND...: run COMMAND, logged; restart it whenever it dies
  local name=$1 code reason now deaths=() recent t count=0 child=""
  shift
  # The launch gone (even killed with SIGKILL), this supervisor gets SIGTERM (its parent-death
  # signal) and takes its node down; the node has SIGKILL as its own, should this one vanish.
  trap '[ -n "$child" ] && kill -INT "$child" 2>/dev/null; exit 0' TERM
  while :; do
    setpriv --pdeathsig KILL -- "$@" >> "$run/log/$name.log" 2>&1 &
    child=$!
    echo "$child" > "$sup/$name.pid"
    wait "$child" 2>/dev/null && code=0 || code=$?  # (bash's own "Killed" notice is not for users)
    [ -e "$sup/stopping" ] && return 0
    reason=$(exit_reason "$code")
    if [ "$respawn" = 0 ]; then
      echo "[launch] $name died ($reason); respawn is off (--no-respawn): stopping the run" >&2
      echo "$name" > "$sup/failed"
      kill -USR1 "$launch_pid" 2>/dev/null
      return 0
    fi
    now=$(date +%s)
    recent=()
    for t in "${deaths[@]}"; do [ $((now - t)) -lt 60 ] && recent+=("$t"); done
    deaths=("${recent[@]}" "$now")
    if [ "${#deaths[@]}" -gt "$max_deaths" ]; then
      echo "[launch] $name died ($reason) more than $max_deaths times within a minute: stopping the run" >&2
      echo "$name" > "$sup/failed"
      kill -USR1 "$launch_pid" 2>/dev/null
      return 0
    fi
    sleep "$respawn_delay"
    [ -e "$sup/stopping" ] && return 0
    count=$((count + 1))
    echo "[launch] $name died ($reason), restarted ($count)"
  done
}
export -f supervise exit_reason
export run sup respawn respawn_delay max_deaths
export launch_pid=$$

cleanup() {
  local code=$?
  trap - EXIT INT TERM USR1
  touch "$sup/stopping"
  # For the benchmarks: CPU seconds of every process of the run (CLARC_CPU_REPORT=FILE).
  if [ -n "${CLARC_CPU_REPORT:-}" ]; then
    local tck name
    tck=$(getconf CLK_TCK)
    for name in "${nodes[@]}"; do  # user + system time, in clock ticks, of each node
      awk -v n="$name" -v t="$tck" '{printf "%s %.2f\n", n, ($14 + $15) / t}' \
        "/proc/$(cat "$sup/$name.pid" 2>/dev/null)/stat" 2>/dev/null || true
    done > "$CLARC_CPU_REPORT"
  fi
  local name
  # The recorder stops last, so that it holds everything the others said until they stopped.
  stop_pids $(for name in "${nodes[@]}"; do [ "$name" = recorder ] || cat "$sup/$name.pid" 2>/dev/null; done)
  [ -z "$record" ] || stop_pids $(cat "$sup/recorder.pid" 2>/dev/null)
  for pid in "${supervisors[@]}"; do wait "$pid" 2>/dev/null || true; done
  if [ -n "$record" ]; then
    sed -n 's/.*\] recorded \(.*\)/[launch] recorded \1/p' "$run/log/recorder.log"
  fi
  exit "$code"
}
stop_pids() {  # stop_pids PID...: SIGINT, then SIGKILL what still runs after 5 s
  local pid
  for pid in "$@"; do kill -INT "$pid" 2>/dev/null || true; done
  for pid in "$@"; do
    for _ in $(seq 50); do kill -0 "$pid" 2>/dev/null || break; sleep 0.1; done
    kill -KILL "$pid" 2>/dev/null || true
  done
}
node_failed() {
  echo "[launch] the run stopped because $(cat "$sup/failed" 2>/dev/null || echo a node) died; see $run/log" >&2
  exit 1
}
trap cleanup EXIT
trap 'exit 130' INT TERM
trap node_failed USR1

start() {  # start NAME COMMAND...: a supervised node of the run, logged to $run/log/NAME.log
  local name=$1
  setpriv --pdeathsig TERM -- bash -c 'supervise "$@"' supervisor "$@" &
  supervisors+=($!)
  nodes+=("$name")
}

echo "[launch] $test_name test for $patient$in_language, scenario $(basename "$scenario"), pace x$scale, ROS_DOMAIN_ID=$ROS_DOMAIN_ID"
echo "[launch] logs: $run/log; results store: $db"
echo "[launch] DSR security: $security${DSR_KEYSTORE:+ (keystore $DSR_KEYSTORE)}"
# The policy says who may write what (and with which claim priority); see docs/FORMAT.md.
start dsr_server dsr_server --ros-args -p world_file:="$root/worlds/clarc_room.json" -p state_dir:="$run/dsr_state" \
  -p policy_file:="$root/src/clarc_bringup/policy/clarc.yaml"
dsr graph --timeout 30 > "$run/log/initial_graph.txt" || { echo "[launch] the DSR server did not start:" >&2; cat "$run/log/dsr_server.log" >&2; exit 1; }
if [ -n "$record" ]; then  # recording from the DSR's first state, before any other node starts
  start recorder dsr_recorder --ros-args -p output:="$record"
  for _ in $(seq 300); do grep -q 'recording to' "$run/log/recorder.log" 2>/dev/null && break; sleep 0.1; done
  grep -q 'recording to' "$run/log/recorder.log" 2>/dev/null ||
    { echo "[launch] the recorder did not start:" >&2; cat "$run/log/recorder.log" >&2; exit 1; }
  echo "[launch] $(sed -n 's/.*\]: \(recording to .*\)/\1/p' "$run/log/recorder.log" | tail -1)"
fi

scaled=(--ros-args -p time_scale:="$scale")
robot_voice=en-us  # espeak-ng's voice for the test's language (scenario.py's voice_for)
[ "$test_language" = en ] || robot_voice=$test_language
start tts tts "${scaled[@]}" -p wav_dir:="$run/audio" -p audio:="$audio" -p voice_rate:="$voice_rate" \
  -p voice:="$robot_voice"
start microphone microphone "${scaled[@]}" -p audio:="$audio" -p wav_file:="$run/audio/microphone.wav"
if [ "$audio" = true ]; then  # the recogniser, on the microphone's stream
  start asr asr --ros-args -p clips_dir:="$run/audio/clips"
fi
start touchscreen touchscreen
start kinect kinect "${scaled[@]}" -p camera_hz:="$camera_hz"
if [ "$camera_hz" != 0 ]; then  # the images into the DSR
  start camera camera
fi
start person person "${scaled[@]}"
start gait_analyser gait_analyser "${scaled[@]}"
start speech speech "${scaled[@]}"
start panel panel "${scaled[@]}"
start pelea pelea "${scaled[@]}" -p outbox_dir:="$outbox"
start patient patient "${scaled[@]}" -p scenario:="$scenario"
[ -n "$viewer_token" ] || viewer_token=$(python -c 'import secrets; print(secrets.token_urlsafe(24))')
start dsr_viewer dsr_viewer --ros-args -p port:="$viewer_port" -p token:="$viewer_token"
start cgamed cgamed --ros-args -p db:="$db" -p port:="$dashboard_port" -p clips_dir:="$run/audio/clips"
# A test started from now on is this run's: the monitor tells it from its start, even when it
# joins (or is restarted) after the test began, and ends when the DSR says it is finished.
since=$(date -u +%Y-%m-%dT%H:%M:%S+00:00)
echo "[launch] DSR viewer: http://127.0.0.1:$viewer_port/?token=$viewer_token"
echo "[launch] clinician's dashboard: http://127.0.0.1:$dashboard_port/ (log in)"
if [ -z "$(clarc user list --db "$db" 2>/dev/null)" ]; then
  echo "[launch] the dashboard has no user yet: clarc user add NAME --role admin --db $db (then clinicians and technicians: --role clinician, --role technician)"
fi
if [ "$wait_start" = 1 ]; then
  echo "[launch] press Start on the clinician's dashboard: http://127.0.0.1:$dashboard_port/"
else  # Start is a request in the DSR: PELEA takes it whenever it is up, even after a restart
  clarc start "$patient" --test "$test_kind" --language "$test_language" --timeout 60 \
    --ros-args -r __node:=clarc_start \
    >> "$run/log/start.log" 2>&1 ||
    { echo "[launch] could not press Start:" >&2; cat "$run/log/start.log" >&2; exit 1; }
fi

# The monitor prints the test as it goes, read from the DSR, and exits 0 when the DSR says the
# test is finished (its result is stored), 1 on PELEA's error or when the time is up; killed,
# it is started again like every node (and tells the test again from its start).
deadline=$(( $(date +%s) + ${timeout%.*} ))
nodes+=(clarc_monitor)
restarts=0
while :; do
  remaining=$(( deadline - $(date +%s) ))
  if [ "$remaining" -le 0 ]; then code=1; echo "[launch] the test did not finish within $timeout s" >&2; break; fi
  # its replica's own news (a resync after a server restart) is not a step: warnings and up only
  setpriv --pdeathsig KILL -- clarc_monitor --ros-args -p timeout:="$remaining.0" -p since:="$since" --log-level warn &
  echo "$!" > "$sup/clarc_monitor.pid"
  wait "$!" 2>/dev/null && code=0 || code=$?
  [ "$code" -le 128 ] && break
  if [ "$respawn" = 0 ]; then
    echo "[launch] clarc_monitor died ($(exit_reason "$code")); respawn is off (--no-respawn): stopping the run" >&2
    code=1
    break
  fi
  restarts=$((restarts + 1))
  echo "[launch] clarc_monitor died ($(exit_reason "$code")), restarted ($restarts)"
done
if [ "$code" -eq 0 ]; then
  echo "[launch] test complete; stored in $db (clarc results --db $db)"
else
  echo "[launch] the test did not complete (exit $code); see $run/log" >&2
fi
exit "$code"
