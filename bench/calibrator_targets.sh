#!/usr/bin/env bash
# The calibrator's target rigs (issue "Calibrate the rigs people actually have"): renders each,
# calibrates it in modes none and mask, and counts per rig and mode the cameras with a full pose,
# those within tolerance (1 deg rotation, 5 deg direction of the centre, after aligning the gauge)
# and those posed outside it (confidently wrong), and the pairs marked success more than 2 deg off.
#
#   bash bench/calibrator_targets.sh BUILD_DIR SCRATCH_DIR [RIG ...]
#
# RIG: plaza surround wide ring8x45 demo640 ring10cm ring8x60 (default: all; demo640 is
# `rigsim demo --width 640 --height 360 --frames 2`, the others 960x540 at 4 spp). Takes about 10 min
# on 2 cores. Prints one line per rig and mode, then the totals over the first five rigs.
set -euo pipefail
build=$(realpath "$1"); scratch=$2; shift 2
rigs=("$@"); [ ${#rigs[@]} -gt 0 ] || rigs=(plaza surround wide ring8x45 demo640 ring10cm ring8x60)
B=$build/apps/rigsim/rigsim
# RIGSIM_LOCK=FILE runs each step under flock FILE (a shared machine: builds and timings wait).
run() { if [ -n "${RIGSIM_LOCK:-}" ]; then flock "$RIGSIM_LOCK" "$@"; else "$@"; fi; }
repo=$(cd "$(dirname "$0")/.." && pwd)
mkdir -p "$scratch"
size="--width 960 --height 540"

make_rig() {  # NAME -> make-rig arguments
  case $1 in
    plaza) echo "ring --cameras 4 --overlap 25 --scene $repo/assets/scenes/plaza.glb --frames 3 --trajectory circle $size" ;;
    surround) echo "surround --scene $repo/assets/scenes/parking.glb --frames 3 --trajectory circle $size" ;;
    wide) echo "wide-baseline --baseline 2 --convergence 30 --scene $repo/assets/scenes/street.glb --frames 3 --trajectory circle $size" ;;
    ring8x45) echo "ring --cameras 8 --spacing 45 --scene $repo/assets/scenes/street.glb --frames 3 --trajectory circle $size" ;;
    demo640) echo "demo" ;;  # rigsim demo's own ring and path, see below
    ring10cm) echo "ring --cameras 4 --radius 0.1 --scene $repo/assets/scenes/street.glb --frames 3 --trajectory circle $size" ;;
    ring8x60) echo "ring --cameras 8 --spacing 60 --scene $repo/assets/scenes/street.glb --frames 3 --trajectory circle $size" ;;
    *) echo "unknown rig $1" >&2; exit 2 ;;
  esac
}
scene_of() { make_rig "$1" | sed -E 's/.*--scene ([^ ]+).*/\1/'; }

for rig in "${rigs[@]}"; do
  d=$scratch/$rig
  if [ ! -f "$d/data/rig.json" ]; then
    rm -rf "$d"; mkdir -p "$d"
    if [ "$rig" = demo640 ]; then  # its calibration is redone below like the others'
      rc=0; run "$B" demo --width 640 --height 360 --frames 2 --no-report --semantics none --out "$d/data" \
        > "$d/render.log" 2>&1 || rc=$?
      [ $rc -eq 0 ] || [ $rc -eq 3 ] || { echo "demo failed (exit $rc): $d/render.log" >&2; exit 1; }
      rm -rf "$d/data/calibration" "$d/data/evaluation.json"
    else
      # shellcheck disable=SC2046
      run "$B" make-rig $(make_rig "$rig") --out "$d/setup" > "$d/make-rig.log"
      run "$B" render --scene "$(scene_of "$rig")" --rig "$d/setup/rig.json" --frames "$d/setup/frames.json" \
        --spp 4 --out "$d/data" > "$d/render.log" 2>&1
    fi
  fi
  rm -rf "$d/data/calibration"
  start=$(date +%s.%N)
  # Exit 3 (not every camera calibrated) is a result here, not a failure.
  rc=0; run "$B" calibrate "$d/data" --semantics none,mask > "$d/calibrate.log" 2>&1 || rc=$?
  [ $rc -eq 0 ] || [ $rc -eq 3 ] || { echo "calibrate failed on $rig (exit $rc): $d/calibrate.log" >&2; exit 1; }
  echo "$rig calibrate $(echo "$(date +%s.%N) - $start" | bc) s" >> "$scratch/times.txt"
done

python3 - "$scratch" "${rigs[@]}" <<'EOF'
import json, sys
scratch, rigs = sys.argv[1], sys.argv[2:]
targets = {"plaza", "surround", "wide", "ring8x45", "demo640"}
total = {}
def overconfident(c):  # evaluation.json's verdict (evaluation/verdicts.h: beyond 3 stated sd and 0.05 deg)
    return c.get("overconfident") is True
print(f"{'rig':10} {'mode':5} {'posed':>6} {'within':>7} {'outside':>8} {'bad pairs':>9} {'overconf':>8}  statuses")
for rig in rigs:
    ev = json.load(open(f"{scratch}/{rig}/data/calibration/evaluation.json"))
    for mode, m in ev["methods"].items():
        cams = m["rig"]["cameras"]
        posed = sum(c["calibrated"] for c in cams)
        within = sum(c["within_tolerance"] is True for c in cams)
        outside = sum(c["calibrated"] and c["within_tolerance"] is False for c in cams)
        bad = sum(1 for p in m["pairs"] if p.get("success") and (p.get("rotation_error_deg") or 0) > 2)
        over = sum(overconfident(c) for c in cams)
        st = "; ".join(f"{c['name']}: {c['status'][:60]}" for c in cams if not c["calibrated"])
        print(f"{rig:10} {mode:5} {posed:>3}/{len(cams):<2} {within:>7} {outside:>8} {bad:>9} {over:>8}  {st}")
        if rig in targets:
            t = total.setdefault(mode, [0, 0, 0, 0, 0, 0])
            for i, v in enumerate((posed, within, outside, bad, len(cams), over)): t[i] += v
for mode, (posed, within, outside, bad, n, over) in total.items():
    print(f"targets {mode}: {posed}/{n} posed ({100*posed/n:.0f}%), {within} within tolerance, {outside} posed outside it, {bad} pairs marked success > 2 deg, {over} overconfident")
EOF
