#!/usr/bin/env bash
# rigsim as an installed program: `cmake --install` into a fresh prefix, then the installed program,
# run from a folder outside the repository, renders and calibrates a small demo and writes the
# report of its dataset, with the data installed beside it (PREFIX/share/rigsim). An installed
# program never falls back to the source tree (common/data_dir.h), so a file the install leaves
# out fails here. Then what it says when its data are missing, and RIGSIM_DATA_DIR.
# Usage: install_test.sh CMAKE BUILD_DIR SOURCE_DIR (ctest passes them; see tests/CMakeLists.txt).
set -euo pipefail
cmake=$1
build=$(cd "$2" && pwd -P)
source=$(cd "$3" && pwd -P)
tmp=$(cd "$(mktemp -d "${TMPDIR:-/tmp}/rigsim_install_test.XXXXXX")" && pwd -P)  # as /proc/self/exe names it
cleanup() {
  local code=$?
  if [ "$code" -eq 0 ]; then rm -rf "$tmp"; else echo "kept $tmp for a look"; fi
}
trap cleanup EXIT
prefix=$tmp/prefix
fail() { echo "install_test: FAILED: $*" >&2; exit 1; }
case $tmp/ in "$source"/* | "$build"/*) fail "the temporary folder $tmp is inside the repository or the build";; esac
unset RIGSIM_DATA_DIR

"$cmake" --install "$build" --prefix "$prefix" > "$tmp/install.log" || { cat "$tmp/install.log"; fail "cmake --install"; }
for f in bin/rigsim share/rigsim/assets/scenes/street.glb share/rigsim/assets/rules/common_names.json \
         share/rigsim/assets/rigs/plaza_ring.json share/rigsim/report/web/index.html share/rigsim/report/web/report.js \
         share/rigsim/report/web/geometry.js share/rigsim/report/web/report.css; do
  [ -f "$prefix/$f" ] || fail "cmake --install did not install $f"
done
rigsim=$prefix/bin/rigsim

mkdir "$tmp/work"
cd "$tmp/work"
# The help names the default scene in words, never the folder rigsim was built in.
commands=$("$rigsim" --help | grep -oE '^  [a-z][a-z-]+ {2,}' | tr -d ' ')
[ "$(wc -w <<< "$commands")" -ge 10 ] || fail "rigsim --help lists no commands: $commands"
for command in "" $commands; do
  help=$("$rigsim" ${command:+"$command"} --help)
  if grep -qF -e "$source" -e "$build" <<< "$help"; then fail "\`rigsim $command --help\` shows the build path"; fi
done
grep -qF "the built-in street" <<< "$("$rigsim" demo --help)" || fail "demo --help does not name the built-in street"

# A classroom-size demo (every camera calibrated at this size) and the report of its dataset.
"$rigsim" demo --out demo --width 640 --height 360 --frames 3 --spp 1 > demo.log 2>&1 || { cat demo.log; fail "rigsim demo"; }
"$rigsim" report demo --out report > report.log 2>&1 || { cat report.log; fail "rigsim report"; }
for d in demo/report report; do
  for f in index.html report.js three/three.min.js three/GLTFLoader.js data/report.js data/scene.js; do
    [ -s "$d/$f" ] || fail "$d/$f is missing"
  done
done
if grep -q "shows the rig alone" report.log; then cat report.log; fail "report did not find the installed street scene"; fi

# Data missing: the installed program says what it looked for, where, and names RIGSIM_DATA_DIR.
rm "$prefix/share/rigsim/assets/scenes/street.glb"
if "$rigsim" demo --out missing > missing.log 2>&1; then fail "demo ran without its scene"; fi
grep -qF "$prefix/share/rigsim/assets/scenes/street.glb: missing" missing.log || { cat missing.log; fail "no message naming the missing scene"; }
grep -qF "RIGSIM_DATA_DIR" missing.log || { cat missing.log; fail "the message does not name RIGSIM_DATA_DIR"; }
rm "$prefix/share/rigsim/report/web/report.css"
if "$rigsim" report demo --out no_page > no_page.log 2>&1; then fail "report ran without its page"; fi
grep -qF "$prefix/share/rigsim/report/web/report.css: missing" no_page.log || { cat no_page.log; fail "no message naming the missing page"; }
if grep -q "calibrating" no_page.log; then fail "report calibrated before finding its page missing"; fi
# A copy of the program with no share/rigsim beside it does not read the source tree either.
mkdir -p "$tmp/loose/bin"
cp "$rigsim" "$tmp/loose/bin/rigsim"
if "$tmp/loose/bin/rigsim" demo --out loose > loose.log 2>&1; then fail "a loose copy of the program found data"; fi
grep -qF "rigsim's data (assets/, report/web/) not found: no $tmp/loose/share/rigsim beside the program" loose.log ||
  { cat loose.log; fail "no message saying where the loose copy looked"; }
# RIGSIM_DATA_DIR wins, and is the only place looked in.
if RIGSIM_DATA_DIR=$tmp/none "$rigsim" demo --out none > none.log 2>&1; then fail "demo ran with RIGSIM_DATA_DIR missing"; fi
grep -qF "RIGSIM_DATA_DIR=$tmp/none: not a folder" none.log || { cat none.log; fail "no message naming RIGSIM_DATA_DIR"; }
mkdir -p "$tmp/own/assets/scenes"
if RIGSIM_DATA_DIR=$tmp/own "$rigsim" demo --out own --no-report > own.log 2>&1; then fail "demo ran with an empty RIGSIM_DATA_DIR"; fi
grep -qF "$tmp/own/assets/scenes/street.glb: missing (rigsim's data folder $tmp/own, from RIGSIM_DATA_DIR" own.log ||
  { cat own.log; fail "RIGSIM_DATA_DIR is not where the scene was looked for"; }
echo "install_test: passed"
