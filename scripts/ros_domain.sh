# Sourced by launch.sh and two_hosts.sh after env.sh: the run's ROS domain, ROS_DOMAIN_ID when the
# caller set it, otherwise the first of a block that no test run, benchmark or other launch on
# this machine holds (dsr_graph/ros/domains.py: a lock file a block). The lock stays with the
# sourcing shell and the processes it starts (they inherit the file) until the last of them ends.
if [ -z "${ROS_DOMAIN_ID:-}" ]; then
  if ! blocks=$(python -m dsr_graph.ros.domains $$); then
    echo "cannot list the ROS domains' lock files (python -m dsr_graph.ros.domains failed);" \
      "set ROS_DOMAIN_ID" >&2
    exit 1
  fi
  while read -r lock first; do
    [ ! -e "$lock" ] || [ -w "$lock" ] || continue  # another user's lock file: their block
    exec {domain_lock}> "$lock"
    if flock -n "$domain_lock"; then
      export ROS_DOMAIN_ID="$first"
      break
    fi
    exec {domain_lock}>&-
  done <<< "$blocks"
  if [ -z "${ROS_DOMAIN_ID:-}" ]; then
    echo "every block of ROS domains is held by test runs, benchmarks or launches on this" \
      "machine; set ROS_DOMAIN_ID" >&2
    exit 1
  fi
fi
