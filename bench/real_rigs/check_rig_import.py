#!/usr/bin/env python3
"""Check make-rig's importers on real calibrations against the real-rig folders' truth.

    python3 bench/real_rigs/check_rig_import.py RIGSIM DGP_CHECKOUT MMDET3D_CHECKOUT DDAD01_DIR NUSCENES_DIR SCRATCH

RIGSIM is the rigsim program. DDAD: `make-rig --type file --rig-file` on DGP_CHECKOUT's
tests/data/dgp/test_scene/scene_01/calibration/*.json as it is (image sizes from the scene JSON
beside it), against DDAD01_DIR/truth_rig.json (the folder prepare_ddad.py writes for scene_01).
nuScenes: the demo sample's calibrated_sensor, sensor and sample_data records rebuilt from
MMDET3D_CHECKOUT's info file (cam2ego = ego_from_cam -> translation and rotation [w, x, y, z],
cam2img -> camera_intrinsic, the photos' sizes), imported the same way, against
NUSCENES_DIR/truth_rig.json (prepare_nuscenes_mmdet3d.py's). Both truths and both imports have the
first camera's frame as the rig frame, so they are compared as they are, camera by camera: rotation
(deg), centre offset (mm), largest intrinsics difference. Prints the table; writes in SCRATCH.
Needs NumPy for the .pkl (Debian: python3-numpy).
"""

import json
import math
import pickle
import subprocess
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
import prepare_nuscenes_mmdet3d as nus  # noqa: E402
import rig_common as rc  # noqa: E402


def rotation_deg(qa, qb):
    """Angle between two rotations, accurate near 0 (atan2 of the relative quaternion)."""
    d = rc.q_mul(rc.q_conj(rc.q_normalize(qa)), rc.q_normalize(qb))
    return math.degrees(2 * math.atan2(rc.norm(d[1:]), abs(d[0])))


def nuscenes_records(mmdet3d, out):
    info_path = Path(mmdet3d) / nus.INFO
    with open(info_path, "rb") as f:
        cams = pickle.load(f)["data_list"][0]["images"]
    calibrated, sensors, samples = [], [], []
    for i, (name, c) in enumerate(cams.items()):
        m = [[float(x) for x in row] for row in c["cam2ego"]]
        q, t = nus.rigid_from_4x4(m)
        calibrated.append({"token": f"cs{i}", "sensor_token": f"s{i}", "translation": t, "rotation": q,
                           "camera_intrinsic": [[float(x) for x in row] for row in c["cam2img"]]})
        sensors.append({"token": f"s{i}", "channel": name, "modality": "camera"})
        w, h = nus.jpeg_size(info_path.parent / c["img_path"])
        samples.append({"token": c["sample_data_token"], "calibrated_sensor_token": f"cs{i}", "width": w, "height": h})
    out.mkdir(parents=True, exist_ok=True)
    for name, records in (("calibrated_sensor", calibrated), ("sensor", sensors), ("sample_data", samples)):
        (out / f"{name}.json").write_text(json.dumps(records, indent=1))
    return out / "calibrated_sensor.json"


def compare(rigsim, rig_file, truth_path, out):
    subprocess.run([rigsim, "make-rig", "--type", "file", "--rig-file", str(rig_file), "--frames", "1", "--out", str(out),
                    "--force"], check=True, stdout=subprocess.DEVNULL)
    imported = {c["name"]: c for c in json.loads((out / "rig.json").read_text())["cameras"]}
    truth = json.loads(Path(truth_path).read_text())["cameras"]
    print(f"{rig_file}\n  against {truth_path} (rig frame: the first camera, {truth[0]['name']}, in both)")
    print(f"  imported order: {', '.join(imported)}")
    for t in truth:
        c = imported[t["name"]]
        dr = rotation_deg(c["cam_from_rig"]["rotation_wxyz"], t["cam_from_rig"]["rotation"])
        centre = rc.centre_in_rig((c["cam_from_rig"]["rotation_wxyz"], c["cam_from_rig"]["translation"]))
        centre_truth = rc.centre_in_rig((t["cam_from_rig"]["rotation"], t["cam_from_rig"]["translation"]))
        dc = 1000 * rc.norm([a - b for a, b in zip(centre, centre_truth)])
        same = c["model"] == t["model"] and (c["width"], c["height"]) == (t["width"], t["height"])
        dp = max(abs(a - b) for a, b in zip(c["params"], t["params"])) if same else float("nan")
        print(f"  {t['name']:16s} {c['model']} {c['width']}x{c['height']}  rotation {dr:.1e} deg  centre {dc:.1e} mm  "
              f"intrinsics {dp:.1e} px" + ("" if same else f"  (truth {t['model']} {t['width']}x{t['height']})"))


def main():
    if len(sys.argv) != 7:
        sys.exit(__doc__)
    rigsim, dgp, mmdet3d, ddad01, nuscenes, scratch = sys.argv[1:]
    scratch = Path(scratch)
    calibrations = sorted((Path(dgp) / "tests/data/dgp/test_scene/scene_01/calibration").glob("*.json"))
    if len(calibrations) != 1:
        sys.exit(f"{dgp}: expected one calibration JSON of scene_01")
    compare(rigsim, calibrations[0], Path(ddad01) / "truth_rig.json", scratch / "ddad01_twin")
    compare(rigsim, nuscenes_records(mmdet3d, scratch / "nuscenes"), Path(nuscenes) / "truth_rig.json",
            scratch / "nuscenes_twin")


if __name__ == "__main__":
    main()
