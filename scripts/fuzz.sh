#!/usr/bin/env bash
# The fuzz targets of tests/fuzz/ (README.md, "Fuzzing"), built by clang with libFuzzer,
# AddressSanitizer and UndefinedBehaviorSanitizer in build-fuzz/ (the core and the loaders
# only: no tests, samples, benchmark, Python or ROS).
#   fuzz.sh build                    configure and build every target
#   fuzz.sh TARGET SECONDS [OPTS]    run one target (fuzz_urdf, ...; built if missing) for
#                                    SECONDS, with any further libFuzzer options
#   fuzz.sh all SECONDS              every target for SECONDS, two at a time, with a fixed
#                                    seed (the CI stage; see below)
# A run starts from the seed corpus tests/fuzz/corpus/<name>/ and keeps what it finds in
# build-fuzz/corpus/<name>/, so a later run goes on from there. A crash, leak, hang (one
# input over 10 s), memory blow-up or sanitizer report fails the run: the input is saved in
# build-fuzz/artifacts/ and the log's end printed; run the target on that file to replay it.
set -euo pipefail
cd "$(dirname "$0")/.."

build=build-fuzz
targets=(fuzz_urdf fuzz_mesh fuzz_octomap fuzz_world_file fuzz_scene fuzz_sdf fuzz_world_api
         fuzz_world_threads)
# Stack traces with function names and lines, where Debian's llvm-symbolizer is installed.
if [ -x /usr/lib/llvm-14/bin/llvm-symbolizer ]; then
  export ASAN_SYMBOLIZER_PATH=/usr/lib/llvm-14/bin/llvm-symbolizer
fi
export ASAN_OPTIONS=detect_leaks=1
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
# Leaks of the libraries pfx reads files with, which pfx cannot fix (each line says why).
export LSAN_OPTIONS=suppressions=$PWD/tests/fuzz/lsan_suppressions.txt

configure_and_build() {
  # -O1 with line tables: what the sanitizers' reports need, at a fraction of -O2 -g's
  # compile time (the sanitizer stage of scripts/test.sh measured it).
  CC=clang CXX=clang++ cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=RelWithDebInfo \
    -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -gline-tables-only -DNDEBUG" \
    -DPFX_SANITIZE=address,undefined -DPFX_BUILD_FUZZ=ON -DPFX_BUILD_TESTS=OFF \
    -DPFX_UNITY_BUILD=ON -DPFX_BUILD_SAMPLES=OFF -DPFX_BUILD_BENCH=OFF -DPFX_BUILD_ROS=OFF \
    -DPFX_BUILD_PYTHON=OFF >/dev/null
  cmake --build "$build" -j"$(nproc)" --target "$@"
}

# Runs one target; its output goes to build-fuzz/logs/<target>.log. Prints one line with the
# executions per second, or the end of the log and the saved input on failure.
run_target() {
  local target=$1 seconds=$2
  shift 2
  local name=${target#fuzz_}
  local log=$build/logs/$target.log
  local seeds=("tests/fuzz/corpus/$name")
  # The same calls on two threads start from the one-thread target's seeds too.
  if [ "$name" = world_threads ]; then seeds+=(tests/fuzz/corpus/world_api); fi
  mkdir -p "$build/corpus/$name" "$build/artifacts" "$build/logs"
  if "$build/bin/$target" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 \
      -print_final_stats=1 -artifact_prefix="$build/artifacts/$target-" "$@" \
      "$build/corpus/$name" "${seeds[@]}" >"$log" 2>&1; then
    local runs rate
    runs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log")
    rate=$(sed -n 's/^stat::average_exec_per_sec: *//p' "$log")
    echo "fuzz.sh: $target passed: $runs inputs in $seconds s ($rate exec/s), corpus $(ls "$build/corpus/$name" | wc -l) files"
  else
    echo "fuzz.sh: $target FAILED; the end of $log:" >&2
    tail -n 60 "$log" >&2
    echo "fuzz.sh: saved inputs (replay: $build/bin/$target FILE):" >&2
    ls "$build/artifacts/$target-"* >&2 || true
    return 1
  fi
}

case ${1:-} in
  build)
    # pfx_fuzz_targets: every target as one, so that two files compile at a time (a list of
    # targets given to cmake --build is built one target after another).
    configure_and_build pfx_fuzz_targets
    ;;
  all)
    seconds=${2:?usage: fuzz.sh all SECONDS}
    failed=0
    # Two at a time, for two cores: each pair's slower run sets the pace.
    for ((i = 0; i < ${#targets[@]}; i += 2)); do
      pids=()
      for target in "${targets[@]:i:2}"; do
        # A fixed seed: the same commit explores the same inputs here as in CI (as far as
        # the machine's speed lets it in the time), so a run by hand before a change lands
        # sees what CI will. Campaigns by hand (fuzz.sh TARGET SECONDS) take random seeds.
        run_target "$target" "$seconds" -seed=1 &
        pids+=($!)
      done
      for pid in "${pids[@]}"; do wait "$pid" || failed=1; done
    done
    exit $failed
    ;;
  fuzz_*)
    target=$1
    seconds=${2:?usage: fuzz.sh TARGET SECONDS [libFuzzer options]}
    shift 2
    [ -x "$build/bin/$target" ] || configure_and_build "$target"
    run_target "$target" "$seconds" "$@"
    ;;
  *)
    echo "usage: fuzz.sh build | fuzz.sh all SECONDS | fuzz.sh fuzz_<target> SECONDS [libFuzzer options]" >&2
    echo "targets: ${targets[*]}" >&2
    exit 2
    ;;
esac
