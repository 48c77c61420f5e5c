#!/usr/bin/env python3
"""Build a rigsim real-rig folder from KITTI_tiny (7 frames of KITTI raw's colour stereo pair) in TRI-ML/packnet-sfm.

    python3 bench/real_rigs/prepare_kitti_tiny.py PACKNET_CHECKOUT OUT [--force]

PACKNET_CHECKOUT is a clone of https://github.com/TRI-ML/packnet-sfm (MIT) at commit
895427c80edb8e624713f0fb834fc497345b7832, the one commit that holds KITTI_tiny/ (it is reachable
only through the pull-request ref refs/pull/74/head: `git fetch origin pull/74/head &&
git checkout 895427c`). Read: KITTI_tiny/2011_09_26/calib_cam_to_cam.txt (KITTI's calibration of
that day) and KITTI_tiny/2011_09_26/2011_09_26_drive_0023_sync/image_0{2,3}/data/*.png (the
rectified, synchronised colour images of cameras 2 and 3, 1242x375 PNG).

In KITTI's rectified frame every camera has the same orientation (R_rect_00) and
P_rect_0i = K_rect [I | t_i] with t_i = cam_i_from_rect0's translation, so
cam_from_rig(image_03) = (identity, t_3 - t_2) with the rig frame = image_02. Writes OUT/rig.json
(PINHOLE from P_rect), OUT/truth_rig.json, OUT/images/<cam>/<NNNN>.png and OUT/README.md.
Standard library only.
"""

import argparse
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
import rig_common as rc  # noqa: E402

DAY = "KITTI_tiny/2011_09_26"
DRIVE = DAY + "/2011_09_26_drive_0023_sync"
CAMS = ["image_02", "image_03"]


def read_calib(path):
    calib = {}
    for line in Path(path).read_text().splitlines():
        if ":" not in line:
            continue
        key, value = line.split(":", 1)
        try:
            calib[key.strip()] = [float(x) for x in value.split()]
        except ValueError:
            calib[key.strip()] = value.strip()
    return calib


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("source", type=Path, help="a clone of TRI-ML/packnet-sfm at commit 895427c")
    ap.add_argument("out", type=Path, help="output folder")
    ap.add_argument("--commit", default="", help="the source's commit for the README (default: git rev-parse)")
    ap.add_argument("--force", action="store_true", help="replace OUT")
    a = ap.parse_args()

    calib = read_calib(a.source / DAY / "calib_cam_to_cam.txt")
    cameras, images, t = [], {}, {}
    k0 = None
    for cam in CAMS:
        i = cam[-2:]
        p = calib[f"P_rect_{i}"]
        fx, cx, fy, cy = p[0], p[2], p[5], p[6]
        if k0 is None:
            k0 = (fx, fy, cx, cy)
        elif (fx, fy, cx, cy) != k0:
            sys.exit("the rectified cameras do not share K_rect")
        # P = K [I | t]: t = K^-1 p4 (K upper triangular, no skew).
        tz = p[11]
        ty = (p[7] - cy * tz) / fy
        tx = (p[3] - cx * tz) / fx
        t[cam] = [tx, ty, tz]
        w, h = (int(round(x)) for x in calib[f"S_rect_{i}"])
        files = sorted((a.source / DRIVE / cam / "data").glob("*.png"))
        images[cam] = [(f"{n:04d}", f) for n, f in enumerate(files)]
        cameras.append({"name": cam, "model": "PINHOLE", "width": w, "height": h, "params": [fx, fy, cx, cy]})
    for cam in cameras:
        cam["cam_from_rig"] = ([1.0, 0.0, 0.0, 0.0], [x - y for x, y in zip(t[cam["name"]], t[CAMS[0]])])
    baseline = rc.norm(cameras[1]["cam_from_rig"][1])
    stems = [f.stem for _, f in images[CAMS[0]]]

    # The car's motion between frames from the OXTS speed (vf, forward velocity, 9th value).
    speeds = []
    for s in stems:
        oxts = a.source / DRIVE / "oxts" / "data" / f"{s}.txt"
        if oxts.exists():
            speeds.append(float(oxts.read_text().split()[8]))
    motion = (f"forward speed from the OXTS data {min(speeds):.1f}–{max(speeds):.1f} m/s at 10 Hz, "
              f"about {sum(speeds) / len(speeds) / 10:.2f} m between frames") if speeds else "speed unknown"

    desc = rc.describe_rig(cameras)
    commit = a.commit or rc.git_commit(a.source)
    readme = f"""# KITTI raw 2011_09_26_drive_0023, colour stereo pair, 7 frames (TRI-ML/packnet-sfm KITTI_tiny)

2 cameras (KITTI's colour cameras 2 and 3, left and right, rectified), {len(stems)} frames at 10 Hz of a
car driving ({motion}), real photographs (1242×375 PNG, rectified and synchronised:
KITTI raw's `_sync` images), from KITTI_tiny in the public repository TRI-ML/packnet-sfm (commit
{commit}, reachable only through the pull-request ref refs/pull/74/head; folder
`{DRIVE}`; the repository is MIT-licensed, KITTI is CC BY-NC-SA 3.0: non-commercial use,
cite Geiger et al., IJRR 2013). Made by `bench/real_rigs/prepare_kitti_tiny.py PACKNET_CHECKOUT OUT`
in the rigsim repository.

- rig.json: PINHOLE intrinsics from P_rect_02 / P_rect_03 of calib_cam_to_cam.txt (the images are
  rectified: no distortion; both cameras share K_rect).
- truth_rig.json: rig frame = image_02; in the rectified frame both cameras have the same
  orientation, so image_03's cam_from_rig is the identity rotation and the translation
  t_3 − t_2 with t_i = K_rect⁻¹ · P_rect_0i[:, 3].

The rig (camera axes: x right, y down, z forward):
""" + "\n".join(f"- {line}" for line in desc) + f"""

Checks and doubts:
- Baseline {baseline:.4f} m, as KITTI's sensor setup sheet gives (0.54 m between the colour
  cameras, rounded). The translation is along x to
  {rc.vector_angle_deg(cameras[1]['cam_from_rig'][1], [-1, 0, 0]):.3f}° (a rectified pair).
- The truth is KITTI's chessboard calibration of that day followed by rectification: the
  rectified cameras are parallel by construction, and how well the photos obey that rests on the
  calibration (KITTI does not state its error; expect a few hundredths to a tenth of a degree).
  A weak test of rotation (the truth is the identity) but a clean one of direction on a
  narrow-baseline pair that moves 7 frames straight ahead; the scale can be given: `--known-distance image_02 image_03 {baseline:.4f}`.
Not for the test suite: use it from bench scripts and VALIDATION.md.
"""
    rc.write_folder(a.out, cameras, images, readme, force=a.force)
    print(f"wrote {a.out}: {len(cameras)} cameras x {len(stems)} frames; baseline {baseline:.4f} m; {motion}")
    for line in desc:
        print("  " + line)


if __name__ == "__main__":
    main()
