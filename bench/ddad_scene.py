#!/usr/bin/env python3
"""Calibration benchmark on a real vehicle rig: ../shared/data/ddad-scene01 (3 cameras of a car, 3 frames).

Builds a rigsim photo folder from the data set (its images, and its truth_rig.json as rig.json so
that calibrate compares every camera with the vehicle's calibration), runs `rigsim calibrate
--semantics none` RUNS times and prints per run what herz_jesus.py prints: the stage times and,
per camera, the rotation and position-direction error after the rig stage with its status.

    python3 bench/ddad_scene.py ../shared/data/ddad-scene01 [--rigsim build/apps/rigsim/rigsim]
        [--work /tmp/ddad-scene01] [--runs 1] [--threads N]

truth_rig.json names each cam_from_rig rotation "rotation" ([w, x, y, z]); rig.json's key is
"rotation_wxyz". The frames are 0.1 s apart in the data set (its README); calibrate reads them from
the images' names when there is no frames.json. Standard library only.
"""

import argparse
import json
import os
import shutil
import statistics
import sys
from pathlib import Path

from herz_jesus import run_once, summarise


def build_folder(data, folder):
    truth = json.loads((data / "truth_rig.json").read_text())
    for cam in truth["cameras"]:
        pose = cam["cam_from_rig"]
        if "rotation" in pose:
            pose["rotation_wxyz"] = pose.pop("rotation")
    if folder.exists():
        shutil.rmtree(folder)
    folder.mkdir(parents=True)
    os.symlink((data / "images").resolve(), folder / "images")
    (folder / "rig.json").write_text(json.dumps(truth, indent=2) + "\n")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("data", type=Path, help="the ddad-scene01 folder (images/, truth_rig.json)")
    ap.add_argument("--rigsim", type=Path, default=Path(__file__).resolve().parent.parent / "build/apps/rigsim/rigsim")
    ap.add_argument("--work", type=Path, default=Path("/tmp/ddad-scene01"), help="scratch folder (replaced)")
    ap.add_argument("--runs", type=int, default=1)
    ap.add_argument("--threads", type=int, default=0, help="calibrate --threads (0: all cores)")
    a = ap.parse_args()
    if not a.rigsim.exists():
        sys.exit(f"{a.rigsim}: no rigsim binary (build first, or give --rigsim)")
    build_folder(a.data, a.work)
    walls = []
    for i in range(a.runs):
        wall, ev, stdout, cmd = run_once(a.rigsim, a.work, a.threads)
        if i == 0:
            print("$ " + " ".join(cmd))
        print(f"run {i + 1}:")
        summarise(wall, ev, stdout)
        for w in ev["methods"]["none"].get("rig", {}).get("warnings", []):
            print(f"    warning: {w}")
        walls.append(wall)
    print(f"wall time over {a.runs} run(s): median {statistics.median(walls):.2f} s")


if __name__ == "__main__":
    main()
