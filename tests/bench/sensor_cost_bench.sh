#!/bin/bash
# What range sensors cost pfx_node, beside its step: the TurtleBot3 burger (base fixed, its
# own 360-beam laser at 5 Hz and IMU included in every run) under the table of the OctoMap
# room tests/loaders/data/room.bt (8 x 6 m at 5 cm, no ground plane), at dt 0.004 s and
# real-time factor 1, run four times: without sensors of ~sensors, with a 1,080-beam laser at
# 40 Hz, with a 16 x 1,800-beam lidar at 10 Hz, and with both. Each run's share of a core is
# the node's processor time (user + system, /proc/PID/stat) over the wall time of a window
# after a warm-up; a sensor's cost is its run's share less the run without it.
#   tests/bench/sensor_cost_bench.sh [BUILD_DIR (build)] [SECONDS per run (20)]
set -euo pipefail
build=$(realpath "${1:-build}")
seconds=${2:-20}
warmup=5
source=$(cd "$(dirname "$0")/../.." && pwd)
export PYENV_VERSION=system
set +u
source "$build/devel/setup.bash"
set -u
port=$((11500 + RANDOM % 400))
export ROS_MASTER_URI=http://localhost:$port
rosmaster --core -p "$port" >/dev/null 2>&1 &
master=$!
trap 'kill -TERM $master 2>/dev/null' EXIT
sleep 2

urdf=$source/urdf/turtlebot3/turtlebot3_burger.urdf
laser='{name: bench_laser, type: ray, link: base_scan, topic: bench_scan, update_rate: 40,
  horizontal_samples: 1080, horizontal_min_angle: -2.35619, horizontal_max_angle: 2.35619,
  range_min: 0.1, range_max: 30.0}'
lidar='{name: bench_lidar, type: ray, link: base_scan, topic: bench_points, update_rate: 10,
  horizontal_samples: 1800, horizontal_min_angle: -3.14159, horizontal_max_angle: 3.14159,
  vertical_samples: 16, vertical_min_angle: -0.2618, vertical_max_angle: 0.2618,
  range_min: 0.1, range_max: 100.0}'
ticks=$(getconf CLK_TCK)

# Processor seconds a process has used so far.
cpu_seconds() {
  awk -v t="$ticks" '{ sub(/^.*\) /, ""); print ($12 + $13) / t }' "/proc/$1/stat"
}

printf 'sensors\tcore_share\tcpu_s\twall_s\n'
for config in none laser lidar both; do
  case $config in
    none) list='[]' ;;
    laser) list="[$laser]" ;;
    lidar) list="[$lidar]" ;;
    both) list="[$laser, $lidar]" ;;
  esac
  rosparam delete /pfx_node >/dev/null 2>&1 || true
  rosparam set /use_sim_time true
  rosparam set -t "$urdf" /robot_description
  rosparam set /pfx_node/sensors "$list"
  "$build/devel/lib/pfx/pfx_node" __name:=pfx_node _urdf_path:="$urdf" \
    _octomap_file:="$source/tests/loaders/data/room.bt" _ground_plane:=false \
    _fixed_base:=true _marker_rate:=0 >"/tmp/sensor_cost_$config.log" 2>&1 &
  node=$!
  sleep "$warmup"
  cpu0=$(cpu_seconds $node)
  wall0=$(date +%s.%N)
  sleep "$seconds"
  cpu1=$(cpu_seconds $node)
  wall1=$(date +%s.%N)
  kill -TERM $node
  wait $node || true
  awk -v c="$config" -v a="$cpu0" -v b="$cpu1" -v s="$wall0" -v e="$wall1" \
    'BEGIN { printf "%s\t%.4f\t%.2f\t%.2f\n", c, (b - a) / (e - s), b - a, e - s }'
done
