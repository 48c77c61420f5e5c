#!/usr/bin/env python3
"""Calibration benchmark on a real vehicle rig: ../shared/data/ddad-scene01 (3 cameras of a car, 3 frames).

Builds a rigsim photo folder from the data set (its images, and its truth_rig.json as rig.json so
that calibrate compares every camera with the vehicle's calibration), runs `rigsim calibrate
--semantics none` RUNS times and prints per run what herz_jesus.py prints: the stage times and,
per camera, the rotation and position-direction error after the rig stage with its status.

    python3 bench/ddad_scene.py ../shared/data/ddad-scene01 [--rigsim build/apps/rigsim/rigsim]
        [--work /tmp/ddad-scene01] [--runs 1] [--threads N] [--mask] [-- CALIBRATE_OPTION ...]

--mask hides the ego car's body from feature detection (`calibrate --mask WORK/masks`): the masks
are not shipped (the photos are not ours); they are drawn here from polygons traced by hand over
frame 0000 of each side camera (full-resolution pixels, a dozen pixels outside the body's edge),
black inside, white outside. The front camera, CAMERA_01, sees no part of the car and has none.

truth_rig.json names each cam_from_rig rotation "rotation" ([w, x, y, z]); rig.json's key is
"rotation_wxyz". The frames are 0.1 s apart in the data set (its README); calibrate reads them from
the images' names when there is no frames.json. Standard library only.
"""

import json
import math
import os
import shutil
import struct
import zlib
from pathlib import Path

from herz_jesus import parse_arguments, run_benchmark

WIDTH, HEIGHT = 1936, 1216

# The ego car's body in each side camera: the dark door and mirror reflections along the bottom and
# the white body panel in the bottom corner (CAMERA_05 right, CAMERA_06 left). (x, y) in pixels.
BODY_POLYGONS = {
    "CAMERA_05": [(330, 1216), (600, 1160), (800, 1123), (880, 1093), (960, 1073), (1050, 1063), (1250, 1068),
                  (1350, 1083), (1450, 1108), (1550, 1138), (1650, 1108), (1750, 1083), (1850, 1066),
                  (1936, 1058), (1936, 1216)],
    "CAMERA_06": [(0, 1050), (100, 1046), (200, 1056), (260, 1075), (320, 1110), (380, 1135), (500, 1108),
                  (600, 1083), (700, 1063), (800, 1050), (900, 1042), (1000, 1063), (1100, 1083), (1200, 1103),
                  (1300, 1128), (1400, 1158), (1500, 1188), (1580, 1216), (0, 1216)],
}


def polygon_mask(polygon, width, height):
    """Rows of a grey mask: 0 at the pixels whose centre is inside the polygon (even-odd), 255 elsewhere.
    Pixel (x, y)'s centre is at (x, y), rigsim's convention; the bottom row's centre is inside a
    polygon whose edge runs along y = HEIGHT."""
    rows = []
    edges = list(zip(polygon, polygon[1:] + polygon[:1]))
    for y in range(height):
        xs = sorted(x0 + (y - y0) * (x1 - x0) / (y1 - y0) for (x0, y0), (x1, y1) in edges
                    if (y0 <= y < y1) or (y1 <= y < y0))
        row = bytearray(b"\xff" * width)
        for a, b in zip(xs[0::2], xs[1::2]):
            lo, hi = max(0, math.ceil(a)), min(width, math.ceil(b))
            row[lo:hi] = bytes(max(0, hi - lo))
        rows.append(bytes(row))
    return rows


def write_grey_png(path, rows, width, height):
    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)
    raw = b"".join(b"\x00" + r for r in rows)
    path.write_bytes(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 0, 0, 0, 0)) +
                     chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b""))


def draw_masks(folder):
    folder.mkdir(parents=True, exist_ok=True)
    for cam, polygon in BODY_POLYGONS.items():
        write_grey_png(folder / f"{cam}.png", polygon_mask(polygon, WIDTH, HEIGHT), WIDTH, HEIGHT)


def build_folder(data, folder, masks=None):
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
    if masks:
        draw_masks(masks)


def print_warnings(ev):
    for w in ev["methods"]["none"].get("rig", {}).get("warnings", []):
        print(f"    warning: {w}")
    for c in ev.get("masks", {}).get("cameras", []):
        if c["file"]:
            print(f"    mask {c['name']}: hides {c['hidden_percent']:.1f} % of the image, removed "
                  f"{c['features_removed']['none']} keypoints over the frames")


def main():
    a = parse_arguments(__doc__.split("\n")[0], "the ddad-scene01 folder (images/, truth_rig.json)",
                        Path("/tmp/ddad-scene01"), 1,
                        lambda ap: ap.add_argument("--mask", action="store_true",
                                                   help="hide the ego car's body (masks drawn into WORK/masks)"))
    masks = a.work / "masks" if a.mask else None
    run_benchmark(a, lambda data, folder: build_folder(data, folder, masks), print_warnings,
                  ["--mask", str(masks)] if masks else [])


if __name__ == "__main__":
    main()
