#!/usr/bin/env bash
# Installs missing dependencies, configures (Release) and builds rigsim into build/.
# Extra arguments are passed to CMake's configure step (e.g. -DRIGSIM_SANITIZE=ON).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
build_dir=${RIGSIM_BUILD_DIR:-build}
cmake -S . -B "$build_dir" -DCMAKE_BUILD_TYPE=Release "$@"
cmake --build "$build_dir" -j"$(nproc)"
