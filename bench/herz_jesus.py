#!/usr/bin/env python3
"""Calibration benchmark on real photographs: Strecha's Herz-Jesus-P8 as a one-frame "rig".

Builds a rigsim photo folder from the data set (each of the 8 images one camera, PINHOLE from
K.txt, the benchmark's poses as the truth in rig.json), runs `rigsim calibrate --semantics none`
RUNS times, and prints per run the wall time, the stage times calibrate reports and the accuracy
(per camera rotation / position-direction error after the rig stage, median pairwise rotation
error).

    python3 bench/herz_jesus.py ../shared/data/herz-jesus-p8 [--rigsim build/apps/rigsim/rigsim]
        [--work /tmp/herz-jesus] [--runs 3] [--threads N] [-- CALIBRATE_OPTION ...]

Options after `--` go to every `rigsim calibrate` run as they are, for example
`-- --intrinsics-sd 0.001,0.5` (the intrinsics' own uncertainty counted in the stated deviations).

The data set layout (see its README.md): images/NNNN.jpg, images/K.txt and gt/NNNN.jpg.camera
(K, distortion, R camera-to-world, C camera centre, width height). cam_from_world is then
(Rᵀ, −Rᵀ·C). K is in OpenCV's pixel convention (centre of the top-left pixel = (0, 0)),
which is rigsim's too. Standard library only.
"""

import argparse
import json
import math
import os
import re
import shutil
import statistics
import subprocess
import sys
import time
from pathlib import Path


def read_numbers(path):
    return [float(x) for x in Path(path).read_text().split()]


def quaternion_wxyz(r):
    """Unit quaternion (w, x, y, z) of a 3x3 rotation matrix given as rows (Shepperd's method)."""
    tr = r[0][0] + r[1][1] + r[2][2]
    if tr > 0:
        s = math.sqrt(tr + 1.0) * 2
        q = [0.25 * s, (r[2][1] - r[1][2]) / s, (r[0][2] - r[2][0]) / s, (r[1][0] - r[0][1]) / s]
    elif r[0][0] > r[1][1] and r[0][0] > r[2][2]:
        s = math.sqrt(1.0 + r[0][0] - r[1][1] - r[2][2]) * 2
        q = [(r[2][1] - r[1][2]) / s, 0.25 * s, (r[0][1] + r[1][0]) / s, (r[0][2] + r[2][0]) / s]
    elif r[1][1] > r[2][2]:
        s = math.sqrt(1.0 + r[1][1] - r[0][0] - r[2][2]) * 2
        q = [(r[0][2] - r[2][0]) / s, (r[0][1] + r[1][0]) / s, 0.25 * s, (r[1][2] + r[2][1]) / s]
    else:
        s = math.sqrt(1.0 + r[2][2] - r[0][0] - r[1][1]) * 2
        q = [(r[1][0] - r[0][1]) / s, (r[0][2] + r[2][0]) / s, (r[1][2] + r[2][1]) / s, 0.25 * s]
    n = math.sqrt(sum(v * v for v in q))
    return [v / n for v in q]


def orthonormalised(r):
    """The rotation nearest to r by Gram-Schmidt on its rows: the files give 6 digits, which
    leaves the matrix orthogonal to ~1e-6 only."""
    rows = []
    for v in r:
        for u in rows:
            d = sum(a * b for a, b in zip(v, u))
            v = [a - d * b for a, b in zip(v, u)]
        n = math.sqrt(sum(a * a for a in v))
        rows.append([a / n for a in v])
    return rows


def camera_entry(name, gt_file):
    v = read_numbers(gt_file)
    if len(v) != 9 + 3 + 9 + 3 + 2:
        sys.exit(f"{gt_file}: expected 26 numbers (K, distortion, R, C, width height), found {len(v)}")
    k, dist, r_cw, c, (w, h) = v[0:9], v[9:12], v[12:21], v[21:24], v[24:26]
    if any(d != 0 for d in dist):
        sys.exit(f"{gt_file}: distortion {dist} is not zero; the images are expected undistorted")
    r_cw = orthonormalised([r_cw[0:3], r_cw[3:6], r_cw[6:9]])
    # cam_from_world: R^T, -R^T C.
    r = [[r_cw[j][i] for j in range(3)] for i in range(3)]
    t = [-sum(r[i][j] * c[j] for j in range(3)) for i in range(3)]
    return {
        "name": name,
        "model": "PINHOLE",
        "width": int(w),
        "height": int(h),
        "params": [k[0], k[4], k[2], k[5]],
        "cam_from_rig": {"rotation_wxyz": quaternion_wxyz(r), "translation": t},
    }


def build_folder(data, folder):
    """rig.json with the truth, images/<cam>/0.jpg (symlinks to the data set's photos)."""
    images = sorted((data / "images").glob("*.jpg"))
    if len(images) < 2:
        sys.exit(f"{data / 'images'}: expected the data set's NNNN.jpg photos, found {len(images)}")
    k_txt = read_numbers(data / "images" / "K.txt")
    if folder.exists():
        shutil.rmtree(folder)
    cameras = []
    for img in images:
        cam = img.stem
        entry = camera_entry(cam, data / "gt" / (img.name + ".camera"))
        if [entry["params"][i] for i in range(4)] != [k_txt[0], k_txt[4], k_txt[2], k_txt[5]]:
            sys.exit(f"{img}: K in gt/ differs from images/K.txt")
        cameras.append(entry)
        (folder / "images" / cam).mkdir(parents=True)
        os.symlink(img.resolve(), folder / "images" / cam / "0.jpg")
    (folder / "rig.json").write_text(json.dumps({"cameras": cameras}, indent=2) + "\n")


def run_once(rigsim, folder, threads, extra_args=()):
    out = folder / "calibration"
    cmd = [str(rigsim), "calibrate", str(folder), "--semantics", "none", "--force"]
    if threads:
        cmd += ["--threads", str(threads)]
    cmd += list(extra_args)
    start = time.monotonic()
    proc = subprocess.run(cmd, capture_output=True, text=True)
    wall = time.monotonic() - start
    if proc.returncode not in (0, 3):  # 3: some camera without a full pose, the results written
        sys.exit(f"{' '.join(cmd)} failed ({proc.returncode}):\n{proc.stdout}\n{proc.stderr}")
    return wall, json.loads((out / "evaluation.json").read_text()), proc.stdout, cmd


def fmt(x, spec):
    return "-" if x is None else format(x, spec)


def summarise(wall, ev, stdout):
    m = ev["methods"]["none"]
    rig = m.get("rig", {})
    t = dict(rig.get("timing", m.get("timing", {})))
    t["screen_time_s"] = m.get("timing", {}).get("screen_time_s", 0.0)
    took = re.search(r"calibration took ([0-9.]+) s", stdout)
    print(f"  wall {wall:.2f} s (calibration {took.group(1) if took else '?'} s, then the outputs); "
          "stage times summed over threads (s):")
    print("    " + ", ".join(f"{k.replace('_time_s', '')} {v:.2f}" for k, v in t.items()))
    cams = rig.get("cameras", [])
    rot = [c.get("rotation_error_deg") for c in cams]
    tdir = [c.get("translation_direction_error_deg") for c in cams]
    print("    camera  rot_err_deg  t_dir_err_deg  status")
    for c in cams:
        print(f"    {c.get('name', '?'):6}  {fmt(c.get('rotation_error_deg'), '11.4f')}  "
              f"{fmt(c.get('translation_direction_error_deg'), '13.3f')}  {c.get('status', '')}")
    pair_rot = [p["rotation_error_deg"] for p in m.get("pairs", []) if p.get("rotation_error_deg") is not None]
    rot_k = [x for x in rot if x is not None]
    tdir_k = [x for x in tdir if x is not None]
    print(f"    median pairwise rotation error {fmt(statistics.median(pair_rot) if pair_rot else None, '.4f')} deg "
          f"({len(pair_rot)} pairs); worst camera rotation {fmt(max(rot_k) if rot_k else None, '.4f')} deg, "
          f"direction {fmt(max(tdir_k) if tdir_k else None, '.3f')} deg")


def parse_arguments(description, data_help, default_work, default_runs, add_arguments=None):
    """The command line both real-data benchmarks share; add_arguments(parser) adds a data set's own."""
    ap = argparse.ArgumentParser(description=description)
    ap.add_argument("data", type=Path, help=data_help)
    ap.add_argument("--rigsim", type=Path, default=Path(__file__).resolve().parent.parent / "build/apps/rigsim/rigsim")
    ap.add_argument("--work", type=Path, default=default_work, help="scratch folder (replaced)")
    ap.add_argument("--runs", type=int, default=default_runs)
    ap.add_argument("--threads", type=int, default=0, help="calibrate --threads (0: all cores)")
    ap.epilog = "options after -- go to every rigsim calibrate run (e.g. -- --intrinsics-sd 0.001,0.5)"
    if add_arguments:
        add_arguments(ap)
    argv = sys.argv[1:]
    split = argv.index("--") if "--" in argv else len(argv)
    a = ap.parse_args(argv[:split])
    a.calibrate_args = argv[split + 1:]
    if not a.rigsim.exists():
        sys.exit(f"{a.rigsim}: no rigsim binary (build first, or give --rigsim)")
    return a


def run_benchmark(a, build_folder, after_run=None, extra_args=()):
    """Builds the photo folder, calibrates it a.runs times (with calibrate's `extra_args`, then the
    user's options after --), prints each run and the wall times; after_run(evaluation) adds what a
    data set has to say of a run."""
    build_folder(a.data, a.work)
    walls = []
    for i in range(a.runs):
        wall, ev, stdout, cmd = run_once(a.rigsim, a.work, a.threads, list(extra_args) + a.calibrate_args)
        if i == 0:
            print("$ " + " ".join(cmd))
        print(f"run {i + 1}:")
        summarise(wall, ev, stdout)
        if after_run:
            after_run(ev)
        walls.append(wall)
    print(f"wall time over {a.runs} run(s): median {statistics.median(walls):.2f} s, "
          f"min {min(walls):.2f} s, max {max(walls):.2f} s")


def main():
    a = parse_arguments(__doc__.split("\n")[0], "the herz-jesus-p8 folder (images/, gt/)", Path("/tmp/herz-jesus"), 3)
    run_benchmark(a, build_folder)


if __name__ == "__main__":
    main()
