#!/usr/bin/env bash
# The main job: installs what is missing, builds the core, the loaders and the ROS node,
# runs the headless samples of the simple and the stable pipeline (driven stage by stage
# through the low-level API), of sleep, of the ragdoll, of a world saved and read back, of
# particles (cloth, hair, a rope) and of the character controller, then the ROS demo (scripts/demo_ros.sh): a rosmaster, the
# ragdoll falling onto the ground in pfx_node with rviz under Xvfb, a raycast and the
# contacts asked for from the command line, and rviz's picture of the scene in
# build/ragdoll.png.
set -euo pipefail
cd "$(dirname "$0")/.."

bash scripts/install_deps.sh all
# ROS's Python tools need Debian's python3, not a pyenv one first on PATH.
export PYENV_VERSION=system
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release -DPYTHON_EXECUTABLE=/usr/bin/python3 >/dev/null
cmake --build build -j"$(nproc)" --target sample_1_simple sample_2_stable sample_3_sleep \
  sample_6_joint sample_7_serialize sample_9_particle_physics sample_10_character_ctrl pfx_node
./build/bin/sample_1_simple
./build/bin/sample_2_stable
./build/bin/sample_3_sleep
./build/bin/sample_6_joint
./build/bin/sample_7_serialize build/sample_7_serialize.pfxw
./build/bin/sample_9_particle_physics
./build/bin/sample_10_character_ctrl

xvfb-run -a -s "-screen 0 1280x960x24" bash scripts/demo_ros.sh build
