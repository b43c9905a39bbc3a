#!/usr/bin/env bash
# Installs, from Debian's packages, what the build needs. Usage: install_deps.sh [core|all]
#   core: compiler, CMake, Eigen, oneTBB (the task manager), GoogleTest, Google Benchmark (the
#         physics core and its tests), pybind11, numpy, pytest and Dask's distributed (the
#         Python module, its sweep over a cluster, and their tests)
#   all:  core plus the loaders (urdfdom, assimp, qhull, OctoMap, cairo, tinyxml2 and
#         libsdformat for scene files), clang with libFuzzer (the fuzz targets), the ROS node
#         (catkin, roscpp, tf2_ros, messages, rostest, rviz under Xvfb) and the benchmark
#         peers (Bullet, ODE, MuJoCo, Embree, gnuplot)
set -euo pipefail

set_name=${1:-core}
core=(build-essential cmake pkg-config libeigen3-dev libtbb-dev libgtest-dev libgmock-dev
  libbenchmark-dev pybind11-dev python3-dev python3-numpy python3-pytest python3-distributed)
packages=("${core[@]}")
if [ "$set_name" = all ]; then
  # The URDF loader reads what urdfdom cannot (capsules) with urdfdom's TinyXML itself.
  packages+=(liburdfdom-dev libtinyxml-dev libassimp-dev libqhull-dev liboctomap-dev libcairo2-dev)
  # Scene files: pfx scene XML through tinyxml2, SDFormat worlds through libsdformat 12.
  packages+=(libtinyxml2-dev libsdformat-dev)
  # The fuzz targets (scripts/fuzz.sh): clang, its runtime libraries (libFuzzer and the
  # sanitizers), and llvm-symbolizer for the stack traces of what a run finds.
  packages+=(clang libclang-rt-14-dev llvm-14)
  # ROS1 from Debian: the message packages come twice, as C++ headers (lib*-dev) and as
  # the .msg definitions that message generation reads (ros-*).
  packages+=(catkin libroscpp-dev libtf2-ros-dev liburdf-dev ros-message-generation
    ros-message-runtime python3-gencpp python3-genmsg librostest-dev python3-rosmaster
    python3-roslaunch python3-rostest rosout rosbash python3-rosservice python3-rostopic
    python3-rosnode tf2-tools python3-numpy)
  for msgs in geometry-msgs std-msgs visualization-msgs sensor-msgs nav-msgs std-srvs \
    diagnostic-msgs trajectory-msgs; do
    packages+=("lib${msgs}-dev" "ros-${msgs}")
  done
  # Python message classes, so that rostopic echo reads the node's topics.
  packages+=(python3-sensor-msgs python3-nav-msgs python3-diagnostic-msgs
    python3-visualization-msgs python3-geometry-msgs python3-std-msgs python3-trajectory-msgs)
  packages+=(libros-rosgraph-msgs-dev ros-rosgraph-msgs)
  packages+=(rviz xvfb xauth imagemagick)
  packages+=(libbullet-dev libbullet-extras-dev libode-dev libmujoco-dev libembree-dev gnuplot-nox)
fi

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
[ ${#missing[@]} -eq 0 ] && exit 0

if [ "$(id -u)" -eq 0 ]; then
  as_root=()
elif command -v sudo >/dev/null; then
  as_root=(sudo)
else
  echo "install_deps.sh: missing packages (${missing[*]}) and no root: run as root" >&2
  exit 1
fi
echo "install_deps.sh: installing ${missing[*]}" >&2
export DEBIAN_FRONTEND=noninteractive
"${as_root[@]}" apt-get update -qq
"${as_root[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
