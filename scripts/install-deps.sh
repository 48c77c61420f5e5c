#!/usr/bin/env bash
# Installs rigsim's dependencies from Debian's packages, skipping what is already there.
# Safe to run repeatedly; needs root (or sudo) only when something is missing.
#   bash scripts/install-deps.sh          what building rigsim and running the demo need
#   bash scripts/install-deps.sh --tests  also what only the tests use (scripts/test.sh)
set -euo pipefail

packages=(
  build-essential cmake pkg-config
  libembree-dev
  libpng-dev libjpeg-dev libtiff-dev libopenexr-dev libwebp-dev  # image files (dataset/image_codecs.h)
  libtinygltf-dev
  libdraco-dev                           # Draco-compressed glTF meshes (gltf/gltf_compression.h)
  libmeshoptimizer-dev                   # meshopt-compressed glTF buffers (gltf/gltf_compression.h)
  libglm-dev
  # The OpenCV modules rigsim links, not the libopencv-dev meta package (every module, with VTK,
  # GDAL, HDF5, FFmpeg). Debian's features2d headers still pull in highgui's (Qt, FFmpeg headers).
  libopencv-core-dev libopencv-imgproc-dev libopencv-features2d-dev libopencv-calib3d-dev
  libopencv-dnn-dev                      # segmentation networks in ONNX (segmentation/segmenter.h)
  libeigen3-dev
  libceres-dev
  nlohmann-json3-dev
  libyaml-cpp-dev                        # sweep configs in YAML (sweep/sweep_config.h)
  gnuplot-nox                            # sweep plots (sweep/sweep_plots.h)
  libjs-three                            # three.js r111, copied into every teaching report (report/)
  libcli11-dev
  libtbb-dev
  libre2-dev                             # label-rule regexes in linear time (gltf/label_rules.h)
  libgtest-dev libgmock-dev libbenchmark-dev  # small; configuring the default build finds them
)
# Large, and used by tests only.
test_packages=(
  clang libclang-rt-14-dev               # fuzzing: clang and libFuzzer (libclang_rt.fuzzer), scripts/fuzz.sh
  libopencv-imgcodecs-dev                # tests encode their input images (PNG, JPEG, WebP) with OpenCV
  colmap                                 # the COLMAP export through COLMAP's tools (tests/colmap_interop_cli_test.cc)
  chromium                               # the report in a real browser (tests/report_browser_test.cc)
)
case "${1:-}" in
  --tests) packages+=("${test_packages[@]}") ;;
  "") ;;
  *) echo "install-deps: unknown argument '$1' (give --tests or nothing)" >&2; exit 1 ;;
esac

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
