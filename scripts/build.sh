#!/usr/bin/env bash
# Installs missing dependencies, configures (Release) and builds rigsim into build/: everything
# (tests and benchmarks too), or only the targets named in RIGSIM_BUILD_TARGETS (scripts/demo.sh
# builds "rigsim" alone). Extra arguments are passed to CMake's configure step
# (e.g. -DRIGSIM_SANITIZE=ON).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
build_dir=${RIGSIM_BUILD_DIR:-build}
cmake -S . -B "$build_dir" -DCMAKE_BUILD_TYPE=Release "$@"
targets=()
for t in ${RIGSIM_BUILD_TARGETS:-}; do targets+=(--target "$t"); done
cmake --build "$build_dir" -j"$(nproc)" "${targets[@]}"
