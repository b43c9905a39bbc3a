#!/usr/bin/env bash
# The test command: installs what is missing, builds everything (core, loaders, the ROS node
# and its rostests), runs every test (labels core, loaders, ros, ...), then builds the core
# again under AddressSanitizer + UndefinedBehaviorSanitizer and runs its tests there too,
# once more in double precision (PFX_DOUBLE) for its core and loader tests, and last runs
# each fuzz target for a bounded time.
set -euo pipefail
cd "$(dirname "$0")/.."

bash scripts/install_deps.sh all
jobs=$(nproc)
# ROS's Python tools need Debian's python3, not a pyenv one first on PATH.
export PYENV_VERSION=system
# Each stage's start and its seconds, so that the CI log shows where the time goes.
stage_started=$SECONDS
stage() {
  echo "== stage: $1 at $(date -u +%T) (previous stage took $((SECONDS - stage_started)) s)"
  stage_started=$SECONDS
}

stage "release build"
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release -DPYTHON_EXECUTABLE=/usr/bin/python3 >/dev/null
cmake --build build -j"$jobs"
stage "release tests"
ctest --test-dir build --output-on-failure -j"$jobs"

stage "sanitizer build"
# -O1 -g1: a quarter of the compile time of -O2 -g (pfx_gjk.cpp: 12 against 50 CPU seconds)
# with line tables, which is what the sanitizers' stack traces need.
cmake -S . -B build-asan -DCMAKE_BUILD_TYPE=RelWithDebInfo -DPFX_SANITIZE=address,undefined \
  -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1 -DNDEBUG" \
  -DPFX_BUILD_SAMPLES=OFF -DPFX_BUILD_BENCH=OFF -DPFX_BUILD_ROS=OFF >/dev/null
# Only the programs of the core tests, the ones run here: the loaders, their tests and the
# extreme suite would double the build for nothing run.
core_targets=$(ls tests/core/test_*.cpp | xargs -n1 basename | sed 's/[.]cpp$//')
cmake --build build-asan -j"$jobs" --target $core_targets
stage "sanitizer tests"
ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1 \
  ctest --test-dir build-asan --output-on-failure -L core -j"$jobs"

# The core in double precision, a build of its own. Only the programs that the core and
# loader tests run are built (no samples, benchmark or extreme suite): about 4 CPU minutes,
# 2.5 minutes on two idle cores.
stage "double build"
cmake -S . -B build-double -DCMAKE_BUILD_TYPE=Release -DPFX_DOUBLE=ON \
  -DPFX_BUILD_SAMPLES=OFF -DPFX_BUILD_BENCH=OFF -DPFX_BUILD_ROS=OFF >/dev/null
double_targets=$(ls tests/core/test_*.cpp tests/loaders/test_*.cpp | xargs -n1 basename | sed 's/[.]cpp$//')
cmake --build build-double -j"$jobs" --target $double_targets pfx_sim_check
stage "double tests"
ctest --test-dir build-double --output-on-failure -L "core|loaders" -j"$jobs"
# The fuzz targets (tests/fuzz/): clang with libFuzzer, ASan and UBSan, a build of the core
# and loaders alone; each target runs 45 s from its seed corpus, two at a time. Any crash,
# leak, hang or sanitizer report fails the run (scripts/fuzz.sh prints the input it saved).
stage "fuzz build"
bash scripts/fuzz.sh build
stage "fuzz runs"
bash scripts/fuzz.sh all 45
stage "done"
echo "all tests passed in $SECONDS s"
