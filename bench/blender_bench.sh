#!/usr/bin/env bash
# Side by side on this machine: Blender Cycles (CPU) against `rigsim render` on the benchmark view
# (the built-in street, the demo rig's first frame: 4 cameras, 1280x720), at the same samples per
# pixel, runs alternating so that both see the same load. Prints one line per run; BENCHMARKS.md
# gives the fastest and the median.
#
#   bash bench/blender_bench.sh BUILD_DIR [RUNS] [SPP...]     e.g. bash bench/blender_bench.sh build 3 4 16
#
# Needs Blender and NumPy (Debian: apt-get install blender python3-numpy; Blender 3.4). Blender
# renders with bench/blender_render.py (one bounce, object-index and depth passes, one multilayer
# EXR per camera); "blender renders" is the sum of its render calls (rendering and writing each
# EXR, without starting Blender and importing the glTF), "blender process" the whole process.
# rigsim is the whole `render` command: loading the scene, rendering, writing the dataset, the
# ground-truth overlap.
set -euo pipefail
build_dir=${1:?usage: blender_bench.sh BUILD_DIR [RUNS] [SPP...]}
runs=${2:-3}
shift $(( $# < 2 ? $# : 2 ))
spps=("${@:-4}")
[ ${#spps[@]} -gt 0 ] || spps=(4 16)
root=$(cd "$(dirname "$0")/.." && pwd)
rigsim=$(cd "$build_dir" && pwd)/apps/rigsim/rigsim
command -v blender > /dev/null || { echo "blender_bench: needs blender (apt-get install blender)" >&2; exit 1; }
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT
scene="$root/assets/scenes/street.glb"
"$rigsim" make-rig ring --position 0,1.6,4 --frames 1 --out "$scratch/rig" > /dev/null

for spp in "${spps[@]}"; do
  for run in $(seq "$runs"); do
    /usr/bin/time -f "%e %U" -o "$scratch/time" blender -b --factory-startup -P "$root/bench/blender_render.py" -- \
      "$scene" "$scratch/rig/rig.json" "$scratch/rig/frames.json" "$spp" "$scratch/blender" > "$scratch/blender.log" 2>&1
    renders=$(sed -n 's/^blender: .* views rendered in \([0-9.]*\) s$/\1/p' "$scratch/blender.log")
    [ -n "$renders" ] || { tail -n 5 "$scratch/blender.log" >&2; echo "blender_bench: Blender did not render" >&2; exit 1; }
    read -r b_wall b_user < "$scratch/time"
    /usr/bin/time -f "%e %U" -o "$scratch/time" "$rigsim" render --scene "$scene" --rig "$scratch/rig/rig.json" \
      --frames "$scratch/rig/frames.json" --out "$scratch/rigsim" --force --spp "$spp" > /dev/null 2>&1
    read -r r_wall r_user < "$scratch/time"
    awk -v spp="$spp" -v run="$run" -v br="$renders" -v bw="$b_wall" -v bu="$b_user" -v rw="$r_wall" -v ru="$r_user" 'BEGIN {
      printf "spp %2d run %d: blender renders %6.2f s (process %6.2f s, user %6.2f s)  rigsim render %5.2f s (user %5.2f s)  ratio %5.1fx (process %5.1fx)\n",
        spp, run, br, bw, bu, rw, ru, br / rw, bw / rw }'
  done
done
