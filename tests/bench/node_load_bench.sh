#!/bin/bash
# pfx_node under load for longer than CI's node_load.test: the same rostest with its phases
# lengthened. Prints the figures: calls per second answered in the paused phase (driven by
# ~step) and in the running phase (real-time factor 1 asked for), the real-time factor the
# node reported on /diagnostics while running (mean and lowest), its RSS after the first
# second, after the paused phase and at the end, and the test's verdict.
#   tests/bench/node_load_bench.sh [BUILD_DIR (build)] [SECONDS per phase (60)] [CLIENTS (4)]
set -euo pipefail
build=$(realpath "${1:-build}")
seconds=${2:-60}
clients=${3:-4}
source=$(cd "$(dirname "$0")/../.." && pwd)
export PYENV_VERSION=system
set +u
source "$build/devel/setup.bash"
set -u
export ROS_HOME=${ROS_HOME:-$build/tests/ros/ros_home}
report=$(mktemp /tmp/pfx_node_load_XXXXXX.tsv)
trap 'rm -f "$report"' EXIT
verdict=passed
rostest "$source/tests/ros/node_load.test" load_seconds:="$seconds" \
  running_seconds:="$seconds" clients:="$clients" report_file:="$report" >/dev/null 2>&1 ||
  verdict=failed
echo "load average at the end: $(cut -d' ' -f1-3 /proc/loadavg)"
cat "$report"
echo "test: $verdict"
[ "$verdict" = passed ]
