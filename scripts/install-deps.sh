#!/usr/bin/env bash
# Installs rigsim's build dependencies from Debian's packages, skipping what is already there.
# Safe to run repeatedly; needs root (or sudo) only when something is missing.
set -euo pipefail

packages=(
  build-essential cmake pkg-config
  libembree-dev
  libopenimageio-dev openimageio-tools   # OIIO's CMake config needs the tools (see DESIGN.md)
  libtinygltf-dev
  libdraco-dev                           # Draco-compressed glTF meshes (gltf/gltf_compression.h)
  libmeshoptimizer-dev                   # meshopt-compressed glTF buffers (gltf/gltf_compression.h)
  libglm-dev
  libopencv-dev
  libeigen3-dev
  libceres-dev
  nlohmann-json3-dev
  libyaml-cpp-dev                        # sweep configs in YAML (sweep/sweep_config.h)
  gnuplot-nox                            # sweep plots (sweep/sweep_plots.h)
  libjs-three                            # three.js r111, copied into every teaching report (report/)
  chromium                               # test only: the report in a real browser (tests/report_browser_test.cc)
  libcli11-dev
  libtbb-dev
  libre2-dev                             # label-rule regexes in linear time (gltf/label_rules.h)
  libgtest-dev libgmock-dev
  libbenchmark-dev
  clang libclang-rt-14-dev               # fuzzing: clang and libFuzzer (libclang_rt.fuzzer), scripts/fuzz.sh
)

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#packages[@]} packages present"
  exit 0
fi

echo "install-deps: installing ${missing[*]}"
sudo_cmd=()
if [ "$(id -u)" -ne 0 ]; then sudo_cmd=(sudo); fi
export DEBIAN_FRONTEND=noninteractive
"${sudo_cmd[@]}" apt-get update -q
"${sudo_cmd[@]}" apt-get install -y -q --no-install-recommends "${missing[@]}"
