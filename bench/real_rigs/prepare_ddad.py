#!/usr/bin/env python3
"""Build a rigsim real-rig folder from a DDAD scene in the test data of TRI-ML/dgp.

    python3 bench/real_rigs/prepare_ddad.py DGP_CHECKOUT OUT [--scene scene_01] [--cameras CAMERA_01,...]
        [--force]

DGP_CHECKOUT is a clone of https://github.com/TRI-ML/dgp (MIT); the scene is read from
tests/data/dgp/test_scene/<scene>/: calibration/*.json (per sensor: the pose of the sensor in the
vehicle frame, "extrinsics", and pinhole "intrinsics"), scene_*.json (per datum: file name and the
sensor's pose in the world) and rgb/<camera>/<timestamp>.jpg. scene_01 has 3 cameras (the folder
../shared/data/ddad-scene01), scene_02 6 (front, front-left/right, rear-left/right, rear). scene_02
is the rig the team holds out (issue "Real rigs"): check the calibrator on it, never tune on it.

Writes OUT/rig.json (intrinsics only), OUT/truth_rig.json (cam_from_rig = inv(vehicle_from_cam) ·
vehicle_from_first camera, rotation [w, x, y, z] under "rotation"), OUT/images/<cam>/<NNNN>.jpg
(frames in time order) and OUT/README.md, and prints how well the per-frame poses of the scene
agree with the calibration (a check of the truth). Standard library only.
"""

import argparse
import json
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
import rig_common as rc  # noqa: E402


def pose(p):
    r, t = p["rotation"], p["translation"]
    return rc.q_normalize([r["qw"], r["qx"], r["qy"], r["qz"]]), [t["x"], t["y"], t["z"]]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("source", type=Path, help="a clone of TRI-ML/dgp")
    ap.add_argument("out", type=Path, help="output folder")
    ap.add_argument("--scene", default="scene_01", help="scene folder under tests/data/dgp/test_scene")
    ap.add_argument("--cameras", default="", help="comma-separated cameras (default: every camera, in the "
                    "calibration's order; the first is the rig frame)")
    ap.add_argument("--commit", default="", help="the source's commit for the README (default: git rev-parse)")
    ap.add_argument("--force", action="store_true", help="replace OUT")
    a = ap.parse_args()

    scene_dir = a.source / "tests/data/dgp/test_scene" / a.scene
    calib_files = sorted((scene_dir / "calibration").glob("*.json"))
    scene_files = sorted(scene_dir.glob("scene_*.json"))
    if len(calib_files) != 1 or len(scene_files) != 1:
        sys.exit(f"{scene_dir}: expected one calibration/*.json and one scene_*.json")
    calib = json.loads(calib_files[0].read_text())
    scene = json.loads(scene_files[0].read_text())

    vehicle_from = {}
    intrinsics = {}
    for name, ext, intr in zip(calib["names"], calib["extrinsics"], calib["intrinsics"]):
        if name.startswith("CAMERA"):
            vehicle_from[name] = pose(ext)
            intrinsics[name] = intr
    names = a.cameras.split(",") if a.cameras else list(vehicle_from)
    for n in names:
        if n not in vehicle_from:
            sys.exit(f"no camera {n} in the calibration (has {', '.join(vehicle_from)})")

    # Per datum: the image's size and its world pose, by file name.
    datum = {}
    for d in scene["data"]:
        img = d["datum"].get("image")
        if img:
            datum[img["filename"]] = img

    images, world_from = {}, {}
    for n in names:
        files = sorted((scene_dir / "rgb" / n).glob("*.jpg"), key=lambda p: int(p.stem))
        images[n] = [(f"{i:04d}", f) for i, f in enumerate(files)]
        world_from[n] = [pose(datum[f"rgb/{n}/{f.name}"]["pose"]) for f in files]
    stems = [[f.stem for _, f in images[n]] for n in names]

    ref = vehicle_from[names[0]]
    cameras = []
    for n in names:
        intr = intrinsics[n]
        img = datum[f"rgb/{n}/{images[n][0][1].name}"]
        if intr.get("skew", 0.0) != 0.0:
            sys.exit(f"{n}: non-zero skew")
        cameras.append({"name": n, "model": "PINHOLE", "width": img["width"], "height": img["height"],
                        "params": [intr["fx"], intr["fy"], intr["cx"], intr["cy"]],
                        "cam_from_rig": rc.compose(rc.inverse(vehicle_from[n]), ref)})

    # Check: cam_from_rig from each frame's world poses against the calibration.
    check = []
    worst_r, worst_t = 0.0, 0.0
    for cam in cameras[1:]:
        n = cam["name"]
        for k in range(len(images[n])):
            from_frames = rc.compose(rc.inverse(world_from[n][k]), world_from[names[0]][k])
            dr = rc.rotation_between_deg(from_frames[0], cam["cam_from_rig"][0])
            dt = rc.norm([x - y for x, y in zip(from_frames[1], cam["cam_from_rig"][1])])
            worst_r, worst_t = max(worst_r, dr), max(worst_t, dt)
    check.append(f"cam_from_rig from the per-frame world poses agrees with the calibration to "
                 f"{worst_r:.2g} deg and {worst_t * 1000:.2g} mm (worst camera and frame)")
    c0 = [world_from[names[0]][k][1] for k in range(len(images[names[0]]))]
    steps = [rc.norm([x - y for x, y in zip(c0[k + 1], c0[k])]) for k in range(len(c0) - 1)]
    turn = rc.rotation_between_deg(world_from[names[0]][0][0], world_from[names[0]][-1][0])
    check.append(f"the first camera moves {', '.join(f'{s:.2f}' for s in steps)} m between frames and turns "
                 f"{turn:.2f} deg from the first frame to the last")
    same_time = all(s == stems[0] for s in stems)
    check.append("every camera's photo of a frame has the same timestamp" if same_time else
                 "the cameras' timestamps differ within a frame: " + "; ".join(
                     f"{n} {', '.join(s)}" for n, s in zip(names, stems)))

    commit = a.commit or rc.git_commit(a.source)
    rel = f"tests/data/dgp/test_scene/{a.scene}"
    desc = rc.describe_rig(cameras)
    readme = f"""# DDAD {a.scene} (TRI-ML/dgp test data) — a real vehicle rig with its factory calibration

{len(cameras)} cameras of a car's surround rig ({', '.join(names)}), {len(images[names[0]])} frames,
real photographs ({cameras[0]['width']}×{cameras[0]['height']} JPEG), from the test data of the public
repository TRI-ML/dgp (folder `{rel}`, commit {commit}; the repository is MIT-licensed, the
images come from Toyota Research Institute's driving data, DDAD, CC BY-NC-SA 4.0: research use).
Made by `bench/real_rigs/prepare_ddad.py DGP_CHECKOUT OUT --scene {a.scene}` in the rigsim repository.

- rig.json: what a user gives `rigsim calibrate` (PINHOLE intrinsics as the dataset gives them, no
  cam_from_rig). images/<cam>/<frame>.jpg as calibrate reads them (frames 0000.. in time order;
  source timestamps (µs·10): {', '.join(stems[0])}).
- truth_rig.json: the same cameras with cam_from_rig from the vehicle's calibration (rig frame =
  {names[0]}, rotation as [w, x, y, z] under the key "rotation"). The dataset gives each sensor's
  pose in the vehicle frame; cam_from_rig = inv(vehicle_from_cam) · vehicle_from_{names[0]}.

The rig (camera axes: x right, y down, z forward):
""" + "\n".join(f"- {line}" for line in desc) + """

Checks of the truth:
""" + "\n".join(f"- {line}" for line in check) + """

The truth is a vehicle calibration, not a survey: trust it to a few tenths of a degree, not to
hundredths (on scene_01 COLMAP and rigsim share about 0.4° of rotation error against it). The
per-frame poses are derived from the same calibration, so their agreement only checks the
conversion. The ego car's body is in the lower part of the side and rear images. Not for the test
suite (a user's clone has no such folder): use it from bench scripts and VALIDATION.md.
"""
    rc.write_folder(a.out, cameras, images, readme, force=a.force)
    print(f"wrote {a.out}: {len(cameras)} cameras x {len(images[names[0]])} frames")
    for line in desc + check:
        print("  " + line)


if __name__ == "__main__":
    main()
