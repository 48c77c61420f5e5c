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

import json
import os
import shutil
from pathlib import Path

from herz_jesus import parse_arguments, run_benchmark


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


def print_warnings(ev):
    for w in ev["methods"]["none"].get("rig", {}).get("warnings", []):
        print(f"    warning: {w}")


def main():
    a = parse_arguments(__doc__.split("\n")[0], "the ddad-scene01 folder (images/, truth_rig.json)",
                        Path("/tmp/ddad-scene01"), 1)
    run_benchmark(a, build_folder, print_warnings)


if __name__ == "__main__":
    main()
