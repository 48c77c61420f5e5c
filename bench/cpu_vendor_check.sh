#!/usr/bin/env bash
# Whether a render is the same bytes on every x86-64 CPU, whoever made it: renders one view of the
# built-in street natively and again under QEMU's user-mode emulator (package qemu-user), whose
# software SSE computes the approximate reciprocals (RCPPS, RSQRTPS) otherwise than this CPU does,
# as Intel's and AMD's CPUs compute them otherwise than each other. Compares every file of the
# two datasets byte for byte and prints, per file, same or differs. Exit 0 when every file is the same, 1 when one differs, 2 on bad usage or a missing
# program. A bench check, never part of the test suite (QEMU is not a dependency of the build).
#
#   bash bench/cpu_vendor_check.sh RIGSIM_BINARY SCRATCH_DIR [WIDTH HEIGHT]
#
# Default 640x360, one camera, 1 spp, one thread; about 20 s (QEMU is 10-30 times slower).
set -euo pipefail
usage() { sed -n '2,12p' "$0" | sed 's/^# \{0,1\}//'; }
if [ "${1:-}" = "-h" ] || [ "${1:-}" = "--help" ]; then usage; exit 0; fi
if [ $# -lt 2 ]; then usage >&2; exit 2; fi
rigsim=$(realpath "$1"); scratch=$2; width=${3:-640}; height=${4:-360}
command -v qemu-x86_64 > /dev/null || { echo "cpu_vendor_check.sh: qemu-x86_64 not found (apt-get install qemu-user)" >&2; exit 2; }
[ -x "$rigsim" ] || { echo "cpu_vendor_check.sh: $1 is not an executable" >&2; exit 2; }
repo=$(cd "$(dirname "$0")/.." && pwd)
scene=$repo/assets/scenes/street.glb
mkdir -p "$scratch"
rm -rf "$scratch/rig" "$scratch/native" "$scratch/emulated"
"$rigsim" make-rig ring --cameras 1 --scene "$scene" --width "$width" --height "$height" --out "$scratch/rig" > /dev/null
render=(render --scene "$scene" --rig "$scratch/rig/rig.json" --frames "$scratch/rig/frames.json" --spp 1 --threads 1)
"$rigsim" "${render[@]}" --out "$scratch/native" > /dev/null
qemu-x86_64 "$rigsim" "${render[@]}" --out "$scratch/emulated" > /dev/null
status=0
while IFS= read -r f; do
  if cmp -s "$scratch/native/$f" "$scratch/emulated/$f"; then
    echo "same     $f"
  else
    status=1
    echo "differs  $f"
  fi
done < <(cd "$scratch/native" && find . -type f ! -name '.rigsim-output' | sed 's|^\./||' | sort)
exit $status
