#!/usr/bin/env bash
# Installs, from Debian's packages, what the build needs. Usage: install_deps.sh [core|all]
#   core: compiler, CMake, Eigen, GoogleTest, Google Benchmark (the physics core and its tests)
#   all:  core plus what later parts use when present (loaders, ROS node, benchmark peers)
set -euo pipefail

set_name=${1:-core}
core=(build-essential cmake pkg-config libeigen3-dev libgtest-dev libgmock-dev libbenchmark-dev)
packages=("${core[@]}")
if [ "$set_name" = all ]; then
  packages+=(libbullet-dev libode-dev libmujoco-dev libqhull-dev gnuplot-nox)
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
