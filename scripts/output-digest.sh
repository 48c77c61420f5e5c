#!/usr/bin/env bash
# Runs rigsim's main workflows into a scratch folder and prints one checksum line per file written,
# so that a change meant to keep outputs byte-identical (a refactor) can be checked:
#
#   bash scripts/output-digest.sh build /tmp/before > before.txt   # on the old commit
#   bash scripts/output-digest.sh build /tmp/after  > after.txt    # on the new one
#   diff before.txt after.txt                                      # empty: nothing changed
#
# Covers generate-scene, make-rig (every type, placed in a scene), render (with --photometric, and
# --sensor automotive),
# calibrate (all four semantic modes, SIFT and ORB, noisy labels, a known distance, intrinsics
# refinement, a ring of little overlap placed through its motion, time offsets and a rolling shutter
# estimated), export (truth and estimate, every format) and the demo. JSON files are checksummed without their timings (keys ending in "time_s", the demo's
# "seconds"): those differ from run to run by nature. Needs jq. Takes about 4 minutes on 2 cores.
set -euo pipefail
build_dir=${1:?usage: output-digest.sh BUILD_DIR SCRATCH_DIR}
scratch=${2:?usage: output-digest.sh BUILD_DIR SCRATCH_DIR}
root=$(cd "$(dirname "$0")/.." && pwd)
rigsim=$(cd "$build_dir" && pwd)/apps/rigsim/rigsim
command -v jq > /dev/null || { echo "output-digest: needs jq (apt-get install jq)" >&2; exit 1; }
rm -rf "$scratch"
mkdir -p "$scratch"
cd "$scratch"
run() { "$rigsim" "$@" > /dev/null 2>> log.txt || { echo "output-digest: failed: rigsim $*" >&2; tail -5 log.txt >&2; exit 1; }; }
# Exit code 3 (a camera without a full pose) is a result, not a failure, for calibrate and demo.
run_calibrate() { "$rigsim" "$@" > /dev/null 2>> log.txt || [ $? -eq 3 ] || { echo "output-digest: failed: rigsim $*" >&2; exit 1; }; }

run generate-scene --preset plaza --seed 3 --out plaza3.glb
run generate-scene --preset parking --seed 2 --animated --out parking2.glb
run inspect plaza3.glb
cp "$root/assets/scenes/parking.glb" parking.glb  # inspect prints the path it was given
"$rigsim" inspect parking.glb > inspect_parking.txt 2>&1

small=(--width 480 --height 270)
run make-rig ring --cameras 4 --overlap 30 --scene "$root/assets/scenes/plaza.glb" --frames 3 "${small[@]}" --out ring
run make-rig surround --scene "$root/assets/scenes/parking.glb" --trajectory circle --circle-radius 12 --frames 3 \
  "${small[@]}" --out surround
run make-rig stereo --frames 2 --jitter-deg 1 --jitter-m 0.01 --seed 5 "${small[@]}" --out stereo
run make-rig wide-baseline --frames 2 "${small[@]}" --out wide

run render --scene "$root/assets/scenes/plaza.glb" --rig ring/rig.json --frames ring/frames.json --out ring_data --spp 2
run render --scene parking2.glb --rig surround/rig.json --frames surround/frames.json --out surround_data --spp 2 \
  --photometric --seed 4
run render --scene "$root/assets/scenes/street.glb" --rig stereo/rig.json --frames stereo/frames.json --out stereo_data
run render --scene "$root/assets/scenes/street.glb" --rig stereo/rig.json --frames stereo/frames.json --out stereo_sensor \
  --sensor automotive --focus-distance 0.5

run_calibrate calibrate ring_data --semantics none,mask,gated,mask+gated --out ring_cal
run_calibrate calibrate surround_data --semantics none --features orb --out surround_cal
run_calibrate calibrate ring_data --semantics mask --labels noisy --known-distance cam0 cam1 0.5 --refine-intrinsics \
  --out ring_cal_refined

# A ring of little overlap on a turning path (the motion stage) and an unsynchronised rolling-shutter
# rig (the time stage).
run make-rig ring --cameras 4 --overlap 2 --scene "$root/assets/scenes/street.glb" --trajectory circle --circle-radius 8 \
  --frames 12 --seed 4 --width 640 --height 360 --out motion
run render --scene "$root/assets/scenes/street.glb" --rig motion/rig.json --frames motion/frames.json --out motion_data --spp 1
run_calibrate calibrate motion_data --semantics none --out motion_cal
run make-rig ring --cameras 3 --overlap 30 --scene "$root/assets/scenes/street.glb" --trajectory handheld --frames 5 \
  --time-offset cam1=0.02 cam2=0.05 --readout 0.03 "${small[@]}" --out timed
run render --scene "$root/assets/scenes/street.glb" --rig timed/rig.json --frames timed/frames.json --out timed_data --spp 1
run_calibrate calibrate timed_data --semantics none --out timed_cal
run_calibrate calibrate timed_data --semantics none --estimate-time-offsets --rolling-shutter --out timed_cal_estimated
run export ring_data --format all --out ring_truth
if [ -f ring_cal/none/rig.json ]; then run export ring_data --format all --rig ring_cal/none/rig.json --out ring_estimate; fi

run_calibrate demo --out demo --frames 2 --spp 2

find . -type f ! -name log.txt | LC_ALL=C sort | while read -r f; do
  case "$f" in
    *.json) printf '%s  %s\n' "$(jq -S 'walk(if type == "object" then with_entries(select((.key | test("time_s$|^seconds$")) | not)) else . end)' "$f" | sha256sum | cut -c1-16)" "$f" ;;
    *) printf '%s  %s\n' "$(sha256sum < "$f" | cut -c1-16)" "$f" ;;
  esac
done
