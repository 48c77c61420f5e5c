#!/usr/bin/env bash
# Builds rigsim's libFuzzer targets (clang, AddressSanitizer + UndefinedBehaviorSanitizer) in
# build-fuzz/ and runs each for a few seconds, starting from its seed corpus in
# tests/fuzz_corpus/<target>/. Exits non-zero when a target crashes; the input that did it is left
# in build-fuzz/artifacts/. Inputs found to reach new code are kept in build-fuzz/corpus/<target>/
# (not in the source tree), so repeated runs go deeper.
#
#   bash scripts/fuzz.sh              # 10 s per target (scripts/test.sh runs 5 s)
#   bash scripts/fuzz.sh 3600         # an hour per target
#   bash scripts/fuzz.sh 600 fuzz_gltf   # one target
#
# RIGSIM_FUZZ_ALSO_BUILD="geometry_test ..." builds those targets (unit tests) in the same build
# before fuzzing: scripts/test.sh runs them under the same sanitizers, so that the libraries are
# compiled with sanitizers once, not twice.
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-${RIGSIM_FUZZ_SECONDS:-10}}
shift || true
build_dir=${RIGSIM_FUZZ_BUILD_DIR:-build-fuzz}
lock=()
if [ -n "${RIGSIM_BUILD_LOCK:-}" ]; then lock=(flock "$RIGSIM_BUILD_LOCK"); fi

targets=("$@")
if [ ${#targets[@]} -eq 0 ]; then
  targets=(fuzz_gltf fuzz_rig_json fuzz_frames_json fuzz_rig_import)
  if [ -f gltf/label_rules.h ]; then targets+=(fuzz_label_rules); fi
fi

also=(${RIGSIM_FUZZ_ALSO_BUILD:-})
with_tests=OFF
if [ ${#also[@]} -gt 0 ]; then with_tests=ON; fi

bash scripts/install-deps.sh --tests  # clang and libFuzzer
mkdir -p "$build_dir"
# Only the libraries the readers need: no renderer, calibrator or CLI.
CC=clang CXX=clang++ "${lock[@]}" cmake -S . -B "$build_dir" -DCMAKE_BUILD_TYPE=Release -DRIGSIM_FUZZ=ON \
  -DRIGSIM_BUILD_TESTS=$with_tests -DRIGSIM_BUILD_BENCHMARKS=OFF \
  -DRIGSIM_SKIP_MODULES="renderer;calibrator;pipeline;apps/rigsim" > "$build_dir/configure.log" 2>&1 ||
  { cat "$build_dir/configure.log"; exit 1; }
"${lock[@]}" cmake --build "$build_dir" --target "${targets[@]}" "${also[@]}" -j"$(nproc)"

mkdir -p "$build_dir/artifacts"
for t in "${targets[@]}"; do
  corpus="$build_dir/corpus/$t"
  mkdir -p "$corpus"
  echo "fuzz: $t for ${seconds}s"
  # -rss_limit_mb / -malloc_limit_mb: an input that makes a reader allocate more is a bug too.
  ASAN_OPTIONS=detect_leaks=1:allocator_may_return_null=1 \
  "$build_dir/fuzz/$t" -max_total_time="$seconds" -timeout=20 -rss_limit_mb=2048 -malloc_limit_mb=1024 \
    -print_final_stats=1 -artifact_prefix="$build_dir/artifacts/$t-" "$corpus" "tests/fuzz_corpus/$t" \
    > "$build_dir/$t.log" 2>&1 || { tail -n 60 "$build_dir/$t.log"; echo "fuzz: $t FAILED (log: $build_dir/$t.log)"; exit 1; }
  grep -E "^(Done|stat::number_of_executed_units|stat::new_units_added)" "$build_dir/$t.log" | tr '\n' ' '
  echo
done
echo "fuzz: ${#targets[@]} targets ran ${seconds}s each without a failure"
