#!/usr/bin/env bash
# The tests: install what is missing, build, run the whole suite (unit and end-to-end).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/build.sh
build_dir=${RIGSIM_BUILD_DIR:-build}
ctest --test-dir "$build_dir" --output-on-failure -j"$(nproc)"
