#!/usr/bin/env python3
"""Build a rigsim real-rig folder from the nuScenes sample in open-mmlab/mmdetection3d's demo data.

    python3 bench/real_rigs/prepare_nuscenes_mmdet3d.py MMDET3D_CHECKOUT OUT [--force]

MMDET3D_CHECKOUT is a clone of https://github.com/open-mmlab/mmdetection3d (Apache-2.0); read from
demo/data/nuscenes/: the info file n015-2018-07-24-11-22-45+0800.pkl (mmdet3d's info format 1.1: per
camera img_path, cam2img = K, cam2ego = ego_from_cam as 4x4, timestamp) and the six camera photos
of that one sample (one key frame of nuScenes v1.0-mini, 1600x900 JPEG).

Writes OUT/rig.json (PINHOLE intrinsics from cam2img), OUT/truth_rig.json (cam_from_rig =
inv(ego_from_cam) · ego_from_CAM_FRONT, rotation [w, x, y, z] under "rotation"),
OUT/images/<cam>/0000.jpg and OUT/README.md.

The .pkl holds NumPy objects, so this needs NumPy (Debian: python3-numpy); nothing else beyond
the standard library.
"""

import argparse
import math
import pickle
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
import rig_common as rc  # noqa: E402

INFO = "demo/data/nuscenes/n015-2018-07-24-11-22-45+0800.pkl"
# Ring order, the front camera first (the rig frame).
ORDER = ["CAM_FRONT", "CAM_FRONT_RIGHT", "CAM_BACK_RIGHT", "CAM_BACK", "CAM_BACK_LEFT", "CAM_FRONT_LEFT"]
WIDTH, HEIGHT = 1600, 900


def rigid_from_4x4(m):
    m = [[float(x) for x in row] for row in m]
    return rc.q_from_matrix([row[:3] for row in m[:3]]), [m[0][3], m[1][3], m[2][3]]


def jpeg_size(path):
    """(width, height) from a JPEG's SOF marker (standard library only)."""
    data = Path(path).read_bytes()
    i = 2
    while i < len(data):
        if data[i] != 0xFF:
            i += 1
            continue
        marker = data[i + 1]
        length = int.from_bytes(data[i + 2:i + 4], "big")
        if marker in (0xC0, 0xC1, 0xC2):
            return int.from_bytes(data[i + 7:i + 9], "big"), int.from_bytes(data[i + 5:i + 7], "big")
        i += 2 + length
    raise ValueError(f"{path}: no JPEG frame header")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("source", type=Path, help="a clone of open-mmlab/mmdetection3d")
    ap.add_argument("out", type=Path, help="output folder")
    ap.add_argument("--commit", default="", help="the source's commit for the README (default: git rev-parse)")
    ap.add_argument("--force", action="store_true", help="replace OUT")
    a = ap.parse_args()

    info_path = a.source / INFO
    with open(info_path, "rb") as f:
        info = pickle.load(f)
    sample = info["data_list"][0]
    cams = sample["images"]
    ego_from = {n: rigid_from_4x4(cams[n]["cam2ego"]) for n in ORDER}
    ref = ego_from[ORDER[0]]
    cameras, images, offsets = [], {}, []
    for n in ORDER:
        c = cams[n]
        k = [[float(x) for x in row] for row in c["cam2img"]]
        if abs(k[0][1]) > 1e-9 or abs(k[1][0]) > 1e-9 or abs(k[2][2] - 1) > 1e-9:
            sys.exit(f"{n}: cam2img is not a pinhole K: {k}")
        src = info_path.parent / c["img_path"]
        w, h = jpeg_size(src)
        cameras.append({"name": n, "model": "PINHOLE", "width": w, "height": h,
                        "params": [k[0][0], k[1][1], k[0][2], k[1][2]],
                        "cam_from_rig": rc.compose(rc.inverse(ego_from[n]), ref)})
        images[n] = [("0000", src)]
        offsets.append(f"{n} {1000 * (float(c['timestamp']) - float(cams[ORDER[0]]['timestamp'])):+.1f} ms")

    fovs = [f"{c['name']} {2 * math.degrees(math.atan(c['width'] / 2 / c['params'][0])):.0f}°" for c in cameras]
    desc = rc.describe_rig(cameras)
    commit = a.commit or rc.git_commit(a.source)
    readme = f"""# nuScenes, one sample (open-mmlab/mmdetection3d demo data) — a real 6-camera vehicle rig

6 cameras of a car's surround rig ({', '.join(ORDER)}), **1 frame** (one key frame of nuScenes
v1.0-mini, log n015-2018-07-24-11-22-45+0800, Singapore), real photographs ({cameras[0]['width']}×{cameras[0]['height']}
JPEG), from the demo data of the public repository open-mmlab/mmdetection3d (folder
`demo/data/nuscenes`, commit {commit}; the repository is Apache-2.0, the nuScenes data are
Motional's, CC BY-NC-SA 4.0: non-commercial research use). Made by
`bench/real_rigs/prepare_nuscenes_mmdet3d.py MMDET3D_CHECKOUT OUT` in the rigsim repository.

- rig.json: PINHOLE intrinsics from the info file's cam2img (nuScenes' camera_intrinsic; nuScenes
  gives no distortion, its photos are used as pinhole images).
- truth_rig.json: cam_from_rig from nuScenes' calibrated_sensor (the info file's cam2ego =
  ego_from_cam), rig frame = CAM_FRONT, cam_from_rig = inv(ego_from_cam) · ego_from_CAM_FRONT,
  rotation as [w, x, y, z] under "rotation".

The rig (camera axes: x right, y down, z forward):
""" + "\n".join(f"- {line}" for line in desc) + f"""

Doubts:
- One time instant only: no motion to link cameras; every camera has to be linked by its
  overlap with a neighbour (nuScenes' neighbours share only a narrow strip). Horizontal fields of
  view from the intrinsics: {'; '.join(fovs)}.
- The cameras are not exposed together: each fires when the lidar sweeps past it. Capture times
  relative to CAM_FRONT: {'; '.join(offsets)}. The car's speed is not in the info file; at
  10 m/s a 40 ms spread moves the car 0.4 m, which biases the relative positions of cameras
  exposed at different times (rotations much less, unless the car turns).
- The truth is nuScenes' vehicle calibration (not a survey): trust it to a few tenths of a degree.
Not for the test suite: use it from bench scripts and VALIDATION.md.
"""
    rc.write_folder(a.out, cameras, images, readme, force=a.force)
    print(f"wrote {a.out}: {len(cameras)} cameras x 1 frame")
    for line in desc:
        print("  " + line)
    print("  capture times: " + "; ".join(offsets))


if __name__ == "__main__":
    main()
