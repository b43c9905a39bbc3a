#!/usr/bin/env bash
# The ROS half of the main job, run inside an X display (demo.sh starts it under xvfb-run):
# starts a rosmaster, launches launch/ragdoll.launch with rviz and the laser post beside the
# ragdoll (a second model, urdf/laser_post.urdf), waits for the ragdoll to fall and come to
# rest, calls the node's raycast and get_contacts services with rosservice, reads the post's
# laser scan, takes a screenshot of rviz (the scan drawn in red) into <build>/ragdoll.png,
# checks that the picture is not blank, and shuts everything down. Usage: demo_ros.sh <build folder>
set -euo pipefail
cd "$(dirname "$0")/.."
build=$(cd "${1:-build}" && pwd)

export PYENV_VERSION=system
export ROS_HOME=$build/ros_home
export ROS_LOG_DIR=$ROS_HOME/log
mkdir -p "$ROS_LOG_DIR"
set +u  # catkin's setup script reads variables that may be unset
# shellcheck disable=SC1091
source "$build/devel/setup.bash"
set -u
# A port of our own, so that a rosmaster someone else runs on 11311 is left alone.
port=$(/usr/bin/python3 -c 'import socket; s = socket.socket(); s.bind(("", 0)); print(s.getsockname()[1])')
export ROS_MASTER_URI=http://localhost:$port

master_pid=
launch_pid=
stop() {
  # Background jobs of a script ignore SIGINT: stop them with SIGTERM, the launch first.
  if [ -n "$launch_pid" ]; then kill -TERM "$launch_pid" 2>/dev/null || true; wait "$launch_pid" 2>/dev/null || true; fi
  if [ -n "$master_pid" ]; then kill -TERM "$master_pid" 2>/dev/null || true; wait "$master_pid" 2>/dev/null || true; fi
}
trap stop EXIT

# Waits up to $1 seconds for the command that follows to succeed.
wait_for() {
  local seconds=$1
  shift
  for _ in $(seq $((seconds * 10))); do
    "$@" >/dev/null 2>&1 && return 0
    sleep 0.1
  done
  echo "demo_ros.sh: timed out waiting for: $*" >&2
  return 1
}

start=$(date +%s%N)
roscore -p "$port" >"$ROS_LOG_DIR/roscore.out" 2>&1 &
master_pid=$!
wait_for 30 rosparam get /rosdistro

roslaunch launch/ragdoll.launch rviz:=true laser_post:=true >"$ROS_LOG_DIR/ragdoll_launch.out" 2>&1 &
launch_pid=$!
if ! wait_for 60 rosservice call /pfx_node/raycast \
  "{origin: {x: 5.0, y: 5.0, z: 1.0}, direction: {x: 0.0, y: 0.0, z: -2.0}}"; then
  tail -n 30 "$ROS_LOG_DIR/ragdoll_launch.out" >&2
  exit 1
fi

# Simulated seconds, from /clock.
sim_time() {
  rostopic echo -n 1 /clock/clock/secs 2>/dev/null | head -n 1
}
wait_for 60 bash -c '[ "$(rostopic echo -n 1 /clock/clock/secs 2>/dev/null | head -n 1)" -ge 5 ]'
echo "pfx_node: t = $(sim_time) s of simulated time; the ragdoll has fallen"
echo

call() {
  echo "\$ rosservice call $1 \"$2\""
  rosservice call "$1" "$2"
}
contacts=$(call /pfx_node/get_contacts "{link: ''}")
echo "$contacts" | head -n 3
# One line per contact point instead of eleven, and the first point where the pelvis (or
# else any link) touches the ground, to aim the raycast below at.
target=$(echo "$contacts" | tail -n +2 | /usr/bin/python3 -c '
import sys, yaml
contacts = yaml.safe_load(sys.stdin)["contacts"]
print("contacts: %d points" % len(contacts), file=sys.stderr)
for c in contacts:
    p, n = c["position"], c["normal"]
    print("  %-10s %-10s at (%6.3f %6.3f %6.3f)  normal (%5.2f %5.2f %5.2f)  depth %.5f m  "
          "impulse %.4f N s" % (c["link_a"], c["link_b"], p["x"], p["y"], p["z"], n["x"], n["y"],
                                n["z"], c["depth"], c["impulse"]), file=sys.stderr)
on_ground = [c for c in contacts if "ground" in (c["link_a"], c["link_b"])]
first = ([c for c in on_ground if "pelvis" in (c["link_a"], c["link_b"])] + on_ground)[0]
print("%.3f %.3f" % (first["position"]["x"], first["position"]["y"]))
' 2>&1 1>"$ROS_HOME/target.txt")
echo "$target"
read -r x y <"$ROS_HOME/target.txt"
echo
echo "A ray straight down from 3 m above that contact point hits the link lying there:"
call /pfx_node/raycast "{origin: {x: $x, y: $y, z: 3.0}, direction: {x: 0.0, y: 0.0, z: -4.0}}"
echo
echo "A ray straight down at (5, 5), away from the ragdoll, hits the ground at z = 0:"
call /pfx_node/raycast "{origin: {x: 5.0, y: 5.0, z: 3.0}, direction: {x: 0.0, y: 0.0, z: -4.0}}"
echo

echo "The laser on the post beside the ragdoll (urdf/laser_post.urdf, spawned from ~models):"
rostopic echo -n 1 /laser_post/scan/ranges | /usr/bin/python3 -c '
import math, sys, yaml
ranges = [float(r) for r in yaml.safe_load(sys.stdin.read().split("---")[0])]
hits = [r for r in ranges if math.isfinite(r)]
print("  /laser_post/scan: %d beams, %d hits from %.2f to %.2f m" % (len(ranges), len(hits), min(hits), max(hits)))
'
echo

# rviz starts while the ragdoll falls; until it has drawn the scene the screen is blank.
picture=$build/ragdoll.png
blank() {
  local colourful
  import -window root "$picture"
  # Share of strongly coloured pixels in the middle of the 3D view: the grid, the ground and
  # the window are grey, the ragdoll's shapes are not.
  colourful=$(convert "$picture" -crop 800x640+420+120 +repage -colorspace HSL -channel G \
    -separate -threshold 40% -format "%[fx:mean]" info:)
  echo "rviz picture: $picture (coloured share of the 3D view: $colourful)"
  /usr/bin/python3 -c "import sys; sys.exit(float('$colourful') > 0.005)"
}
sleep 2
for attempt in $(seq 30); do
  blank || break
  if [ "$attempt" -eq 30 ]; then
    echo "demo_ros.sh: rviz does not show the ragdoll" >&2
    exit 1
  fi
  sleep 1
done

stop
trap - EXIT
echo "ROS demo: $((($(date +%s%N) - start) / 1000000)) ms from starting the rosmaster to shutting everything down"
