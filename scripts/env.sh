# Source this file (`source scripts/env.sh`) for a shell in which every console script of the
# suite (dsr, dsr_server, ...) is on PATH and the built interfaces (dsr_msgs) import.
# It does not install anything: run scripts/setup.sh first (scripts/test.sh and
# scripts/launch.sh do that for you).

_dsr_root=$(cd "$(dirname "${BASH_SOURCE[0]:-$0}")/.." && pwd)
if [ ! -f "$_dsr_root/install/setup.bash" ] || [ ! -x "$_dsr_root/.venv/bin/python" ]; then
  echo "scripts/env.sh: the workspace is not set up; run $_dsr_root/scripts/setup.sh first" >&2
  return 1 2>/dev/null || exit 1
fi

# colcon's and venv's scripts read unset variables: allow that while sourcing them, even when
# the caller runs under `set -u` (scripts/test.sh does).
case $- in *u*) _dsr_nounset=1; set +u ;; *) _dsr_nounset= ;; esac
# shellcheck disable=SC1091
source "$_dsr_root/.venv/bin/activate"
# The venv is the ROS prefix the wheels installed into; colcon's install/ overlays it.
export AMENT_PREFIX_PATH="$_dsr_root/.venv${AMENT_PREFIX_PATH:+:$AMENT_PREFIX_PATH}"
export CMAKE_PREFIX_PATH="$_dsr_root/.venv${CMAKE_PREFIX_PATH:+:$CMAKE_PREFIX_PATH}"
# shellcheck disable=SC1091
source "$_dsr_root/install/setup.bash"

# ament_python puts console scripts in install/<pkg>/lib/<pkg> (where `ros2 run` looks);
# put them on PATH too so that `dsr`, `dsr_server`, ... are plain commands.
for _dsr_bin in "$_dsr_root"/install/*/lib/*; do
  case "$_dsr_bin" in
    */lib/python*) ;;
    *) [ -d "$_dsr_bin" ] && PATH="$_dsr_bin:$PATH" ;;
  esac
done
export PATH
export DSR_WORKSPACE="$_dsr_root"
# The suite's Fast DDS profile (a gone participant is noticed in 2 s, not 20 s: see the file),
# unless the caller chose a profile of their own.
export FASTRTPS_DEFAULT_PROFILES_FILE="${FASTRTPS_DEFAULT_PROFILES_FILE:-$_dsr_root/src/dsr_graph/config/fastdds_profile.xml}"
[ -n "$_dsr_nounset" ] && set -u
unset _dsr_root _dsr_bin _dsr_nounset
