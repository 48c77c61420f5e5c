#!/usr/bin/env bash
# The main job: install what is missing, build the rigsim program (not the tests: scripts/test.sh
# builds those), render the built-in street with the default 4-camera ring rig, calibrate it with
# semantics off and on, and print how close it came.
# Arguments are passed to `rigsim demo` (see `rigsim demo --help`).
set -euo pipefail
cd "$(dirname "$0")/.."
RIGSIM_BUILD_TARGETS=rigsim bash scripts/build.sh
build_dir=${RIGSIM_BUILD_DIR:-build}
"$build_dir"/apps/rigsim/rigsim demo --out out/demo --force "$@"
