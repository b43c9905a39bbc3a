#!/usr/bin/env bash
# The test command: installs what is missing, builds everything (core, loaders, the ROS node
# and its rostests), runs every test (labels core, loaders, ros, ...), then builds the core
# again under AddressSanitizer + UndefinedBehaviorSanitizer and runs its tests there too,
# and once more in double precision (PFX_DOUBLE) for its core and loader tests.
set -euo pipefail
cd "$(dirname "$0")/.."

bash scripts/install_deps.sh all
jobs=$(nproc)
# ROS's Python tools need Debian's python3, not a pyenv one first on PATH.
export PYENV_VERSION=system

cmake -S . -B build -DCMAKE_BUILD_TYPE=Release -DPYTHON_EXECUTABLE=/usr/bin/python3 >/dev/null
cmake --build build -j"$jobs"
ctest --test-dir build --output-on-failure -j"$jobs"

cmake -S . -B build-asan -DCMAKE_BUILD_TYPE=RelWithDebInfo -DPFX_SANITIZE=address,undefined \
  -DPFX_BUILD_SAMPLES=OFF -DPFX_BUILD_BENCH=OFF -DPFX_BUILD_ROS=OFF >/dev/null
# Only the programs of the core tests, the ones run here: the loaders, their tests and the
# extreme suite would double the build for nothing run.
core_targets=$(ls tests/core/test_*.cpp | xargs -n1 basename | sed 's/[.]cpp$//')
cmake --build build-asan -j"$jobs" --target $core_targets
ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1 \
  ctest --test-dir build-asan --output-on-failure -L core -j"$jobs"

# The core in double precision, a build of its own. Only the programs that the core and
# loader tests run are built (no samples, benchmark or extreme suite): about 4 CPU minutes,
# 2.5 minutes on two idle cores.
cmake -S . -B build-double -DCMAKE_BUILD_TYPE=Release -DPFX_DOUBLE=ON \
  -DPFX_BUILD_SAMPLES=OFF -DPFX_BUILD_BENCH=OFF -DPFX_BUILD_ROS=OFF >/dev/null
double_targets=$(ls tests/core/test_*.cpp tests/loaders/test_*.cpp | xargs -n1 basename | sed 's/[.]cpp$//')
cmake --build build-double -j"$jobs" --target $double_targets pfx_sim_check
ctest --test-dir build-double --output-on-failure -L "core|loaders" -j"$jobs"
echo "all tests passed"
