#!/usr/bin/env python3
"""Calibrate a real-rig folder (prepare_*.py's output) with rigsim and score it against its truth_rig.json.

    python3 bench/real_rigs/run.py FOLDER [--rigsim build/apps/rigsim/rigsim] [--work /tmp/real-rigs-run]
        [--threads N] [-- EXTRA CALIBRATE OPTIONS]

Runs `rigsim calibrate FOLDER --semantics none --out WORK/<name>/calibration` (nothing is written
into FOLDER), builds WORK/<name>/truth/ (truth_rig.json as rig.json, "rotation" renamed
"rotation_wxyz", images/ a link to FOLDER/images) and runs `rigsim evaluate WORK/<name>/truth
WORK/<name>/calibration --json WORK/<name>/evaluate.json`, printing evaluate's tables. Standard
library only.
"""

import argparse
import json
import os
import shutil
import subprocess
import sys
from pathlib import Path


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("folder", type=Path)
    ap.add_argument("--rigsim", default="build/apps/rigsim/rigsim")
    ap.add_argument("--work", type=Path, default=Path("/tmp/real-rigs-run"))
    ap.add_argument("--threads", type=int, default=0)
    ap.add_argument("extra", nargs="*", help="further calibrate options (after --)")
    a = ap.parse_args()

    folder = a.folder.resolve()
    work = (a.work / folder.name).resolve()
    truth_dir = work / "truth"
    if truth_dir.exists():
        shutil.rmtree(truth_dir)
    truth_dir.mkdir(parents=True)
    truth = json.loads((folder / "truth_rig.json").read_text())
    for cam in truth["cameras"]:
        pose = cam["cam_from_rig"]
        pose["rotation_wxyz"] = pose.pop("rotation")
    (truth_dir / "rig.json").write_text(json.dumps(truth, indent=1) + "\n")
    os.symlink(folder / "images", truth_dir / "images")

    calib = work / "calibration"
    cmd = [a.rigsim, "calibrate", str(folder), "--semantics", "none", "--out", str(calib), "--force",
           "--threads", str(a.threads)] + a.extra
    print("$ " + " ".join(cmd), flush=True)
    rc = subprocess.run(cmd).returncode
    if rc not in (0, 3):
        sys.exit(f"calibrate failed with exit code {rc}")
    cmd = [a.rigsim, "evaluate", str(truth_dir), str(calib), "--json", str(work / "evaluate.json"), "--force"]
    print("$ " + " ".join(cmd), flush=True)
    sys.exit(subprocess.run(cmd).returncode)


if __name__ == "__main__":
    main()
