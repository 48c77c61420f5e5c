#!/usr/bin/env bash
# Builds COLMAP >= 4 once, from a mirrored git repository of its source, with
# Debian's packages only, into a cache that bench/real_rigs/peers.py finds.
# A bench tool, never part of the test suite: it installs packages and takes
# about 20-40 minutes on 2 cores.
set -euo pipefail

usage() {
  cat <<'EOF'
Usage: bench/colmap4/build.sh [options]

Builds COLMAP >= 4 (GUI, CUDA, ONNX, MVS, OpenGL and CGAL off) from a git
mirror of its source into a cache folder, installing the build dependencies
from Debian with apt-get (it prints what it installs). A second run finds the
cache and does nothing. Prints the path of the colmap binary on its last line.

Options:
  --colmap-repo DIR   git directory of COLMAP's source
                      (default /work/.mirror/colmap+colmap/repo)
  --poselib-repo DIR  git directory of PoseLib's source, used instead of
                      COLMAP's download of it (default
                      /work/.mirror/PoseLib+PoseLib/repo)
  --ref REF           tag or commit to build (default: the newest tag >= 4.0,
                      else HEAD)
  --cache DIR         where builds are kept (default
                      $RIGSIM_COLMAP_CACHE or ~/.cache/rigsim); the result
                      goes to DIR/colmap-<version>
  --jobs N            parallel compile jobs (default 2; run under nice 19)
  --no-apt            do not run apt-get (the dependencies are already there)
  --print-path        print where the binary of this ref is or would be, and
                      exit without building
  -h, --help          this help
EOF
}

colmap_repo=/work/.mirror/colmap+colmap/repo
poselib_repo=/work/.mirror/PoseLib+PoseLib/repo
ref=""
cache="${RIGSIM_COLMAP_CACHE:-$HOME/.cache/rigsim}"
jobs=2
apt=1
print_path=0

die() { echo "bench/colmap4/build.sh: error: $*" >&2; exit 1; }

while [ $# -gt 0 ]; do
  case "$1" in
    --colmap-repo) colmap_repo="${2:?--colmap-repo needs a folder}"; shift 2 ;;
    --poselib-repo) poselib_repo="${2:?--poselib-repo needs a folder}"; shift 2 ;;
    --ref) ref="${2:?--ref needs a tag or commit}"; shift 2 ;;
    --cache) cache="${2:?--cache needs a folder}"; shift 2 ;;
    --jobs) jobs="${2:?--jobs needs a number}"; shift 2 ;;
    --no-apt) apt=0; shift ;;
    --print-path) print_path=1; shift ;;
    -h|--help) usage; exit 0 ;;
    *) usage >&2; die "unknown argument '$1'" ;;
  esac
done

case "$jobs" in ''|*[!0-9]*) die "--jobs must be a positive number, not '$jobs'" ;; esac
git --git-dir="$colmap_repo" rev-parse --verify -q HEAD >/dev/null ||
  die "$colmap_repo is not a git repository of COLMAP's source (--colmap-repo)"

# The newest release tag of major version 4 or later; HEAD when there is none.
if [ -z "$ref" ]; then
  ref=$(git --git-dir="$colmap_repo" tag --list |
        grep -E '^v?[0-9]+\.[0-9]+(\.[0-9]+)?$' |
        awk -F. '{ m = $1; sub(/^v/, "", m); if (m + 0 >= 4) print }' |
        sort -V | tail -n 1 || true)
  [ -n "$ref" ] || ref=HEAD
fi
commit=$(git --git-dir="$colmap_repo" rev-parse --verify -q "$ref^{commit}") ||
  die "$colmap_repo has no tag or commit '$ref'"
if git --git-dir="$colmap_repo" show-ref --verify -q "refs/tags/$ref"; then
  version="${ref#v}"
else
  version="commit-${commit:0:10}"
fi

prefix="$cache/colmap-$version"
binary="$prefix/bin/colmap"
if [ "$print_path" = 1 ]; then echo "$binary"; exit 0; fi

if [ -x "$binary" ] && "$binary" -h >/dev/null 2>&1; then
  echo "COLMAP $version is already built: $binary (nothing to do)"
  echo "$binary"
  exit 0
fi

echo "Building COLMAP $version (commit $commit) into $prefix"

# Debian's packages for what COLMAP 4 finds with find_package. OpenImageIO's
# CMake files come with openimageio-tools, not with libopenimageio-dev; OpenGL
# and GLEW are required by COLMAP's CMake even with the GUI off; faiss is
# Debian's instead of COLMAP's download of it.
packages=(
  build-essential cmake ninja-build git
  libboost-graph-dev libboost-program-options-dev libboost-system-dev
  libeigen3-dev libopenimageio-dev openimageio-tools libmetis-dev
  libsqlite3-dev libgl-dev libglew-dev libsuitesparse-dev libceres-dev
  libgoogle-glog-dev libgflags-dev libfaiss-dev libopenblas-dev
)
if [ "$apt" = 1 ]; then
  [ "$(id -u)" = 0 ] || die "installing packages needs root; run as root or pass --no-apt"
  echo "apt-get update, then apt-get install: ${packages[*]}"
  apt-get update -qq
  DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends "${packages[@]}"
fi

mkdir -p "$cache"
# Sources and build tree stay next to the cache so that an interrupted build
# resumes; the result is installed to a staging folder and moved into place
# only when `colmap -h` of it runs, so the cache never holds a half build.
work="$cache/colmap-$version.build"
src="$work/src"
build="$work/build"
stage="$work/stage"
if [ ! -f "$src/CMakeLists.txt" ]; then
  rm -rf "$src"; mkdir -p "$src"
  git --git-dir="$colmap_repo" archive "$commit" | tar -x -C "$src"
fi

# PoseLib: COLMAP downloads a pinned commit with FetchContent; with no network
# it is taken from the mirror, at that commit when the mirror has it, else at
# the mirror's HEAD (said below).
poselib_src="$work/poselib"
if [ ! -f "$poselib_src/CMakeLists.txt" ]; then
  git --git-dir="$poselib_repo" rev-parse --verify -q HEAD >/dev/null ||
    die "$poselib_repo is not a git repository of PoseLib's source (--poselib-repo)"
  pinned=$(grep -oE 'PoseLib/archive/[0-9a-f]{40}' "$src/src/thirdparty/CMakeLists.txt" |
           head -n 1 | sed 's|.*/||' || true)
  poselib_commit=""
  if [ -n "$pinned" ] && git --git-dir="$poselib_repo" cat-file -e "$pinned^{commit}" 2>/dev/null; then
    poselib_commit="$pinned"
    echo "PoseLib: COLMAP's pinned commit $pinned"
  else
    poselib_commit=$(git --git-dir="$poselib_repo" rev-parse HEAD)
    echo "PoseLib: the mirror lacks COLMAP's pinned commit ${pinned:-(none found)};" \
         "using the mirror's HEAD $poselib_commit"
  fi
  rm -rf "$poselib_src"; mkdir -p "$poselib_src"
  git --git-dir="$poselib_repo" archive "$poselib_commit" | tar -x -C "$poselib_src"
fi

# Newer COLMAP calls PoseLib's relpose_6pt_onesided_focal, which newer PoseLib
# no longer has. It serves only the relative pose of a camera without a focal
# prior; every camera the bench gives COLMAP has its intrinsics, so the solver
# is replaced by one that finds no model (the estimator then falls back on
# others) rather than leaving COLMAP unbuildable.
onesided="$src/src/colmap/estimators/solvers/relpose_one_sided_focal.cc"
if [ -f "$onesided" ] && grep -q 'relpose_6pt_onesided_focal.h' "$onesided" &&
   [ ! -f "$poselib_src/PoseLib/solvers/relpose_6pt_onesided_focal.h" ]; then
  echo "Patching out relpose_6pt_onesided_focal (absent from this PoseLib;" \
       "used only for cameras without a focal prior): $onesided"
  python3 - "$onesided" <<'PY'
import re, sys
path = sys.argv[1]
text = open(path).read()
text = text.replace('#include <PoseLib/solvers/relpose_6pt_onesided_focal.h>',
                    '// relpose_6pt_onesided_focal is absent from this PoseLib (rigsim bench build).')
# Comment out the call statement: from the call to the end of its statement.
new, n = re.subn(r'poselib::relpose_6pt_onesided_focal\([^;]*\);',
                 '/* relpose_6pt_onesided_focal absent: no models */', text, flags=re.S)
if n == 0:
    sys.exit(f"{path}: no call of poselib::relpose_6pt_onesided_focal to patch out")
open(path, 'w').write(new)
PY
fi

mkdir -p "$build"
if [ ! -f "$build/build.ninja" ]; then
  cmake -S "$src" -B "$build" -G Ninja \
    -DCMAKE_BUILD_TYPE=Release \
    -DCMAKE_INSTALL_PREFIX="$stage" \
    -DGUI_ENABLED=OFF -DCUDA_ENABLED=OFF -DONNX_ENABLED=OFF -DMVS_ENABLED=OFF \
    -DOPENGL_ENABLED=OFF -DCGAL_ENABLED=OFF -DDOWNLOAD_ENABLED=OFF \
    -DTESTS_ENABLED=OFF -DIPO_ENABLED=OFF -DCCACHE_ENABLED=OFF \
    -DFETCH_POSELIB=ON -DFETCHCONTENT_SOURCE_DIR_POSELIB="$poselib_src" \
    -DFETCHCONTENT_FULLY_DISCONNECTED=ON \
    -DFETCH_FAISS=OFF
fi
nice -n 19 cmake --build "$build" -j "$jobs"
rm -rf "$stage"
cmake --install "$build" >/dev/null
"$stage/bin/colmap" -h >/dev/null 2>&1 || die "the built $stage/bin/colmap does not run 'colmap -h'"
rm -rf "$prefix"
mv "$stage" "$prefix"
echo "COLMAP $version built: $binary"
"$binary" -h 2>&1 | head -n 2
echo "$binary"
