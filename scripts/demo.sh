#!/usr/bin/env bash
# The main job: installs what is missing, builds, and runs the stable-pipeline demo (a box
# pyramid falling onto the ground and settling) and the ragdoll demo (joints with limits,
# dropped onto the ground), printing what happened.
set -euo pipefail
cd "$(dirname "$0")/.."

bash scripts/install_deps.sh core
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j"$(nproc)" --target sample_2_stable sample_6_joint
./build/bin/sample_2_stable
./build/bin/sample_6_joint
