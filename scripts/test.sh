#!/usr/bin/env bash
# The tests: install what is missing (what only the tests use too: install-deps.sh --tests), then
#   1. build everything (build/, Release) and run the whole suite, unit and end-to-end (ctest);
#   2. build the fuzz targets, the unit tests of the readers and the geometry (geometry, labels,
#      dataset, scene, gltf) and the bad-input test once, with clang, AddressSanitizer and
#      UndefinedBehaviorSanitizer (build-fuzz/, RIGSIM_FUZZ), and fuzz each reader for a few
#      seconds (scripts/fuzz.sh; RIGSIM_FUZZ_SECONDS, default 5 here: a check that the seed corpora
#      still pass and a short search; scripts/fuzz.sh alone runs longer);
#   3. run those unit tests under the sanitizers, each split in two shards run side by side.
# Exits non-zero when any step fails. RIGSIM_TEST_QUICK=1 runs step 1 only. BENCHMARKS.md gives
# what each step costs.
set -euo pipefail
cd "$(dirname "$0")/.."
start=$SECONDS
lock=()
if [ -n "${RIGSIM_BUILD_LOCK:-}" ]; then lock=(flock "$RIGSIM_BUILD_LOCK"); fi
# Each step's line gives the time elapsed and the CPU time (user, system) of everything run so far.
step() { echo; echo "=== test.sh: $* ($((SECONDS - start)) s elapsed; CPU $(times | tail -1))"; }

step "1/3 build and run the whole suite"
bash scripts/install-deps.sh --tests
"${lock[@]}" bash scripts/build.sh
build_dir=${RIGSIM_BUILD_DIR:-build}
ctest --test-dir "$build_dir" --output-on-failure -j"$(nproc)"
if [ "${RIGSIM_TEST_QUICK:-0}" = 1 ]; then exit 0; fi

step "2/3 clang build with AddressSanitizer + UndefinedBehaviorSanitizer (build-fuzz/), and fuzzing"
# One sanitizer build serves the fuzz targets and these tests.
# Procedural scenes and rig placement (procedural/, rigs/) read no user file: their tests run in step 1 only.
sanitizer_tests=(geometry/geometry_test labels/labels_test dataset/dataset_test scene/scene_test gltf/gltf_test
  tests/bad_input_test)
fuzz_dir=${RIGSIM_FUZZ_BUILD_DIR:-build-fuzz}
RIGSIM_FUZZ_ALSO_BUILD="${sanitizer_tests[*]##*/}" bash scripts/fuzz.sh "${RIGSIM_FUZZ_SECONDS:-5}"

step "3/3 unit tests under AddressSanitizer + UndefinedBehaviorSanitizer"
export ASAN_OPTIONS=detect_leaks=1:strict_string_checks=1:detect_stack_use_after_return=1
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
export LSAN_OPTIONS=suppressions=$PWD/scripts/lsan-suppressions.txt
# GoogleTest's sharding splits each test binary over the cores.
shards=$(nproc)
for t in "${sanitizer_tests[@]}"; do
  echo "sanitizers: $t ($shards shards)"
  pids=()
  for ((i = 0; i < shards; ++i)); do
    GTEST_TOTAL_SHARDS=$shards GTEST_SHARD_INDEX=$i "$fuzz_dir/$t" --gtest_brief=1 \
      > "$fuzz_dir/${t##*/}.shard$i.log" 2>&1 &
    pids+=($!)
  done
  for ((i = 0; i < shards; ++i)); do
    wait "${pids[$i]}" || { cat "$fuzz_dir/${t##*/}.shard$i.log"; echo "sanitizers: $t shard $i FAILED"; exit 1; }
    grep -E "^\[  (PASSED|FAILED) " "$fuzz_dir/${t##*/}.shard$i.log" || true
  done
done
unset ASAN_OPTIONS UBSAN_OPTIONS LSAN_OPTIONS

step "all tests passed in $((SECONDS - start)) s"
