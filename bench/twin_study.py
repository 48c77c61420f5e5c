#!/usr/bin/env python3
"""The twin study: a real rig's photos and its twin's renders, calibrated alike, side by side.

    python3 bench/twin_study.py REAL_FOLDER --rigsim build/apps/rigsim/rigsim --work /tmp/twin-study
        [--presets ideal,automotive] [--ego-vehicle] [--placement road] [--scene SCENE.glb]
        [--frames N] [--step M] [--frame-interval S] [--rig-height H] [--spp 2] [--seed 1] [--threads 0]

REAL_FOLDER is a real-rig folder as bench/real_rigs/prepare_*.py write it (the layout of
../shared/data/ddad-scene01): images/<camera>/<frame>.<ext>, the rig with its truth in
truth_rig.json (or a rig.json whose every camera has a cam_from_rig), and frames.json when the
rig's poses are known.

1. WORK/real/: the truth as rig.json (so that calibrate scores itself against it) and a link to
   the folder's images/; `rigsim calibrate WORK/real --semantics none --out WORK/real/calibration`.
2. WORK/twin/rig/: `rigsim make-rig --type file --rig-file WORK/real/rig.json --scene SCENE
   --placement road --frames N --step M [--ego-vehicle]`: the twin on the street (the shipped
   street.glb unless --scene), on a straight path like the photos': N frames M metres apart,
   from frames.json's poses when the folder has them, else N the photos per camera and M --step
   (which is then needed: 0 for a rig that stood still). --frames and --step override either.
3. Per sensor preset: `rigsim render ... --sensor PRESET --out WORK/twin/PRESET` and
   `rigsim calibrate WORK/twin/PRESET --semantics none --out WORK/twin/PRESET-calibration`.
4. One table, printed and written to WORK/twin_study.md and WORK/twin_study.json: cameras placed
   (full pose; and with a rotation only), per camera pair matches, inliers, inlier ratio,
   rotation error and the fit, the median rotation error over the solved pairs, and each
   twin's figures over the real photos' ("ok" when within 2x, the sim-to-real targets:
   the median pair rotation error, and matches and inlier ratios pair by pair; the same
   cameras placed).

A progress line per step; each rigsim command's output goes to WORK/logs/. Runs take minutes: a
1936x1216 render is 30-60 s on 2 cores, a calibration one to a few minutes. Standard library only.
"""

import argparse
import json
import os
import re
import shutil
import statistics
import subprocess
import sys
import time
from pathlib import Path

sys.dont_write_bytecode = True  # importing rig_common must not write into the source tree
sys.path.insert(0, str(Path(__file__).resolve().parent / "real_rigs"))
import rig_common as rc  # noqa: E402

ROOT = Path(__file__).resolve().parent.parent
TARGET_FACTOR = 2.0  # the sim-to-real targets: twin within 2x of the real photos
IMAGE_SUFFIXES = {".png", ".jpg", ".jpeg", ".webp", ".tif", ".tiff", ".exr"}


# ---- what a calibration gave, and the twin against the real photos (pure functions) ----

def pair_fit(pair):
    """How a pair came out: its two-view fit, or why there is none."""
    if pair.get("success"):
        fit = pair.get("pair_type") or "solved"
        return fit + (", beyond tolerance" if pair.get("within_tolerance") is False else "")
    reason = pair.get("failure_reason") or ""
    return "screened out" if reason.startswith("screened out") else "not solved"


def summarise_calibration(evaluation, method="none"):
    """The study's figures of one calibrate run (its evaluation.json, parsed)."""
    m = evaluation["methods"][method]
    cameras = m["rig"]["cameras"]
    pairs = {}
    solved = []
    for p in m["pairs"]:
        if p["cam_a"] == p["cam_b"]:
            continue
        ok = bool(p.get("success"))
        pairs[f"{p['cam_a']}-{p['cam_b']}"] = {
            "matches": p.get("matches", 0),
            "inliers": p.get("inliers", 0) if ok else 0,
            "inlier_ratio": p.get("inlier_ratio") if ok else None,
            "rotation_error_deg": p.get("rotation_error_deg") if ok else None,
            "fit": pair_fit(p),
        }
        if ok and p.get("rotation_error_deg") is not None:
            solved.append(p["rotation_error_deg"])
    return {
        "cameras": [c["name"] for c in cameras],
        "placed": [c["name"] for c in cameras if c.get("calibrated")],
        "rotation_only": [c["name"] for c in cameras if not c.get("calibrated") and c.get("rotation_wxyz") is not None],
        "pairs": pairs,
        "solved_pairs": len(solved),
        "median_pair_rotation_error_deg": statistics.median(solved) if solved else None,
    }


def ratio_against(twin, real, factor=TARGET_FACTOR):
    """twin / real and whether it is within `factor` either way. Both zero (or both absent) agree
    with no ratio; one absent, or a real zero against a twin's other value, does not."""
    if twin is None and real is None:
        return {"ratio": None, "within": True}
    if twin is None or real is None:
        return {"ratio": None, "within": False}
    if real == 0:
        return {"ratio": None, "within": twin == 0}
    r = twin / real
    return {"ratio": r, "within": 1.0 / factor <= r <= factor}


def compare_with_real(real, twin, factor=TARGET_FACTOR):
    """Each figure of a twin over the real photos', and the targets it meets."""
    pairs = {}
    for key, rp in real["pairs"].items():
        tp = twin["pairs"].get(key, {})
        pairs[key] = {q: ratio_against(tp.get(q), rp[q], factor)
                      for q in ("matches", "inliers", "inlier_ratio", "rotation_error_deg")}
    median = ratio_against(twin["median_pair_rotation_error_deg"], real["median_pair_rotation_error_deg"], factor)
    same_placed = sorted(twin["placed"]) == sorted(real["placed"])
    return {
        "pairs": pairs,
        "median_pair_rotation_error_deg": median,
        "targets": {
            "median_pair_rotation_error_within": median["within"],
            "matches_within_every_pair": all(p["matches"]["within"] for p in pairs.values()),
            "inlier_ratio_within_every_pair": all(p["inlier_ratio"]["within"] for p in pairs.values()),
            "same_cameras_placed": same_placed,
        },
        "factor": factor,
    }


def _deg(x):
    return "-" if x is None else f"{x:.3f}°"


def _num(x, spec="d"):
    return "-" if x is None else format(x, spec)


def _ratio_cell(c):
    if c["ratio"] is None:  # both without a value (or both 0) agree; one without does not
        return "same" if c["within"] else "off"
    return f"{c['ratio']:.2f}x " + ("ok" if c["within"] else "off")


def table_rows(columns):
    """The table as rows of cells. columns: [(title, summary, comparison or None)], the real photos
    first (comparison None), then each twin. Every twin column is followed by its ratio column."""
    header = ["", columns[0][0]]
    for title, _, _ in columns[1:]:
        header += [title, "twin/real"]
    rows = [header]

    def row(label, value, compared=None):
        cells = [label, value(columns[0][1])]
        for _, summary, comparison in columns[1:]:
            cells.append(value(summary))
            cells.append(compared(comparison) if compared else "")
        rows.append(cells)

    def placed(s):
        return f"{len(s['placed'])} of {len(s['cameras'])}" + (f" ({', '.join(s['placed'])})" if s["placed"] else "")

    row("cameras placed (full pose)", placed,
        lambda c: "same" if c["targets"]["same_cameras_placed"] else "differ")
    row("cameras with a rotation only", lambda s: ", ".join(s["rotation_only"]) or "-")
    for key in columns[0][1]["pairs"]:
        def get(q, fmt):
            return lambda s: fmt(s["pairs"].get(key, {}).get(q))
        row(f"{key} fit", get("fit", lambda x: x or "-"))
        row(f"{key} matches", get("matches", _num), lambda c: _ratio_cell(c["pairs"][key]["matches"]))
        row(f"{key} inliers", get("inliers", _num), lambda c: _ratio_cell(c["pairs"][key]["inliers"]))
        row(f"{key} inlier ratio", get("inlier_ratio", lambda x: _num(x, ".3f")),
            lambda c: _ratio_cell(c["pairs"][key]["inlier_ratio"]))
        row(f"{key} rotation error", get("rotation_error_deg", _deg),
            lambda c: _ratio_cell(c["pairs"][key]["rotation_error_deg"]))
    row("median pair rotation error",
        lambda s: _deg(s["median_pair_rotation_error_deg"]) + f" ({s['solved_pairs']} solved)",
        lambda c: _ratio_cell(c["median_pair_rotation_error_deg"]))
    return rows


def targets_line(title, comparison):
    """Which of the sim-to-real targets a twin meets, naming the pairs that miss one."""
    t, f = comparison["targets"], comparison["factor"]

    def missing(q):
        off = [k for k, p in comparison["pairs"].items() if not p[q]["within"]]
        return "yes" if not off else "no (" + ", ".join(off) + ")"
    return (f"{title}: median pair rotation error within {f:g}x: {'yes' if t['median_pair_rotation_error_within'] else 'no'}; "
            f"matches within {f:g}x in every pair: {missing('matches')}; "
            f"inlier ratios within {f:g}x in every pair: {missing('inlier_ratio')}; "
            f"the same cameras placed: {'yes' if t['same_cameras_placed'] else 'no'}")


def markdown_table(rows):
    out = ["| " + " | ".join(rows[0]) + " |", "|" + "---|" * len(rows[0])]
    out += ["| " + " | ".join(r) + " |" for r in rows[1:]]
    return "\n".join(out)


def text_table(rows):
    widths = [max(len(r[i]) for r in rows) for i in range(len(rows[0]))]
    return "\n".join("  ".join(c.ljust(w) for c, w in zip(r, widths)).rstrip() for r in rows)


# ---- the real folder and the path of its photos ----

def frames_from_poses(frames_json):
    """(frames, mean step in metres, mean frame interval in seconds or None, turn in degrees) of a
    frames.json with every frame's rig_from_world; None when it has no poses."""
    frames = frames_json.get("frames") if isinstance(frames_json, dict) else None
    if not frames or not all(isinstance(f, dict) and "rig_from_world" in f for f in frames):
        return None
    poses = [((f["rig_from_world"]["rotation_wxyz"]), f["rig_from_world"]["translation"]) for f in frames]
    centres = [rc.inverse(p)[1] for p in poses]
    steps = [rc.norm([a - b for a, b in zip(c1, c0)]) for c0, c1 in zip(centres, centres[1:])]
    times = [f.get("timestamp_s") for f in frames]
    interval = None
    if len(frames) > 1 and all(t is not None for t in times):
        interval = (times[-1] - times[0]) / (len(frames) - 1)
    turn = rc.rotation_between_deg(poses[0][0], poses[-1][0])
    return len(frames), (statistics.mean(steps) if steps else 0.0), interval, turn


def count_photos(folder, camera):
    d = folder / "images" / camera
    if not d.is_dir():
        raise SystemExit(f"{folder}: no images/{camera}/ (the photos of the rig's first camera)")
    n = sum(1 for f in d.iterdir() if f.suffix.lower() in IMAGE_SUFFIXES)
    if n == 0:
        raise SystemExit(f"{d}: no photos")
    return n


# ---- running rigsim ----

class Runner:
    def __init__(self, rigsim, logs):
        self.rigsim = rigsim
        self.logs = logs

    def run(self, name, args, ok_codes=(0,)):
        """Runs rigsim with args, its output into logs/NAME.log; stops with the log's end on failure."""
        log = self.logs / f"{name}.log"
        cmd = [str(self.rigsim)] + [str(a) for a in args]
        start = time.monotonic()
        with open(log, "w") as f:
            f.write("$ " + " ".join(cmd) + "\n")
            f.flush()
            rc_ = subprocess.run(cmd, stdout=f, stderr=subprocess.STDOUT).returncode
        took = time.monotonic() - start
        if rc_ not in ok_codes:
            tail = log.read_text().splitlines()[-15:]
            raise SystemExit(f"{' '.join(cmd)}\nfailed with exit code {rc_} after {took:.0f} s; the end of {log}:\n  "
                             + "\n  ".join(tail))
        return took, log.read_text()


def find_rigsim(given):
    path = Path(given)
    if not path.is_file() and os.sep not in given:
        found = shutil.which(given)
        path = Path(found) if found else path
    if not path.is_file():
        raise SystemExit(f"--rigsim {given}: no such program (build it with bash scripts/build.sh, or give its path)")
    if not os.access(path, os.X_OK):
        raise SystemExit(f"--rigsim {given}: not executable")
    return path.resolve()


def sensor_presets(rigsim):
    """The sensor presets the program knows, from `sweep --list-params`; None when it does not say."""
    try:
        out = subprocess.run([str(rigsim), "sweep", "--list-params"], capture_output=True, text=True, timeout=60).stdout
    except (OSError, subprocess.TimeoutExpired) as e:
        raise SystemExit(f"--rigsim {rigsim}: cannot run it ({e})")
    m = re.search(r"^\s*sensor\s.*\{([^}]*)\}\s*$", out, re.M)
    return [s.strip() for s in m.group(1).split(",")] if m else None


def write_atomically(path, text):
    tmp = path.with_name(path.name + ".tmp")
    tmp.write_text(text)
    os.replace(tmp, path)


def parse_arguments(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter,
                                 epilog="\n".join(__doc__.split("\n")[6:]))
    ap.add_argument("real", type=Path, metavar="REAL_FOLDER",
                    help="a real-rig folder: images/<camera>/, truth_rig.json (or rig.json with poses)")
    ap.add_argument("--rigsim", default=str(ROOT / "build/apps/rigsim/rigsim"),
                    help="the rigsim program (default: build/apps/rigsim/rigsim of this checkout)")
    ap.add_argument("--work", type=Path, default=Path("/tmp/twin-study"),
                    help="scratch folder: its real/, twin/ and logs/ are replaced (default %(default)s)")
    ap.add_argument("--presets", default="ideal,automotive",
                    help="render --sensor presets of the twin, comma-separated (default %(default)s)")
    ap.add_argument("--ego-vehicle", action="store_true", help="make-rig --ego-vehicle: the twin gets its own car body")
    ap.add_argument("--placement", choices=["road", "structure"], default="road",
                    help="make-rig --placement (default %(default)s: in a lane, heading along the street)")
    ap.add_argument("--scene", type=Path, default=ROOT / "assets/scenes/street.glb",
                    help="the glTF scene the twin is placed in (default: the shipped street)")
    ap.add_argument("--frames", type=int, help="frames of the twin's path (default: the real folder's)")
    ap.add_argument("--step", type=float,
                    help="metres between the twin's frames (default: from the folder's frames.json poses; "
                         "needed without them, 0 for a rig that stood still)")
    ap.add_argument("--frame-interval", type=float, help="seconds between frames (default: frames.json's, else 0.1)")
    ap.add_argument("--rig-height", type=float, help="make-rig --rig-height: the first camera's height (default rigsim's)")
    ap.add_argument("--spp", type=int, default=2, help="render --spp (default %(default)s)")
    ap.add_argument("--seed", type=int, default=1, help="make-rig and render --seed (default %(default)s)")
    ap.add_argument("--threads", type=int, default=0, help="render and calibrate --threads (0: all cores)")
    return ap.parse_args(argv)


def check_arguments(a):
    """The real folder, the rigsim program and the presets, each checked before anything runs."""
    real = a.real.resolve()
    if not real.is_dir():
        raise SystemExit(f"{a.real}: no such folder (a real-rig folder: images/<camera>/ and truth_rig.json)")
    if not (real / "images").is_dir():
        raise SystemExit(f"{a.real}: no images/ folder (the photos, images/<camera>/<frame>.jpg)")
    if not a.scene.is_file():
        raise SystemExit(f"--scene {a.scene}: no such file")
    if a.frames is not None and a.frames < 1:
        raise SystemExit("--frames: at least 1")
    rigsim = find_rigsim(a.rigsim)
    presets = [p.strip() for p in a.presets.split(",") if p.strip()]
    if not presets:
        raise SystemExit("--presets: give at least one sensor preset")
    if len(set(presets)) != len(presets):
        raise SystemExit("--presets: a preset is named twice")
    known = sensor_presets(rigsim)
    unknown = [p for p in presets if known is not None and p not in known]
    if unknown:
        raise SystemExit(f"--presets: unknown sensor preset {', '.join(unknown)}; {rigsim.name} knows {', '.join(known)}")
    return real, rigsim, presets


def photos_path(a, real, first_camera):
    """(frames, step in metres, frame interval in seconds, where they came from) of the twin's path:
    the folder's frames.json poses when it has them, else the photos per camera and --step; the
    options override either."""
    n_frames, step, interval, source = None, None, None, None
    frames_file = real / "frames.json"
    if frames_file.is_file():
        try:
            frames_json = json.loads(frames_file.read_text())
            from_poses = frames_from_poses(frames_json)
        except (ValueError, KeyError, TypeError, IndexError) as e:
            raise SystemExit(f"{frames_file}: not a frames.json with rig_from_world per frame ({e})")
        if from_poses:
            n_frames, step, interval, turn = from_poses
            source = "frames.json's poses"
            if turn > 5:
                print(f"note: the photos' rig turns {turn:.0f}° over its frames; the twin drives straight")
    if n_frames is None:
        n_frames = count_photos(real, first_camera)
        source = ("--frames" if a.frames is not None else "the photos per camera") + " and --step"
    elif a.frames is not None or a.step is not None:
        source += " and the options given"
    n_frames = a.frames if a.frames is not None else n_frames
    step = a.step if a.step is not None else step
    if step is None:
        raise SystemExit(f"{a.real}: no frames.json with the rig's poses, so the distance between frames is "
                         "unknown: give --step (metres; 0 for a rig that stood still)")
    interval = a.frame_interval if a.frame_interval is not None else interval
    return n_frames, step, (interval if interval and interval > 0 else 0.1), source


def main(argv=None):
    a = parse_arguments(argv)
    real, rigsim, presets = check_arguments(a)
    truth = rc.truth_rig_json(real)
    n_frames, step, interval, source = photos_path(a, real, truth["cameras"][0]["name"])

    work = a.work.resolve()
    for sub in ("real", "twin", "logs"):
        if (work / sub).exists():
            shutil.rmtree(work / sub)
    for name in ("twin_study.md", "twin_study.json"):  # an earlier run's table is not this one's
        (work / name).unlink(missing_ok=True)
    (work / "logs").mkdir(parents=True)
    runner = Runner(rigsim, work / "logs")
    threads = ["--threads", a.threads]
    steps_total = 2 + 2 * len(presets)
    step_no = [0]

    def progress(what):
        step_no[0] += 1
        print(f"[{step_no[0]}/{steps_total}] {what}", flush=True)

    # 1. The real photos, scored against their truth.
    real_dir = work / "real"
    real_dir.mkdir()
    (real_dir / "rig.json").write_text(json.dumps(truth, indent=1) + "\n")
    os.symlink(real / "images", real_dir / "images")
    if (real / "frames.json").is_file():
        os.symlink(real / "frames.json", real_dir / "frames.json")
    progress(f"calibrating the real photos of {a.real} ({len(truth['cameras'])} cameras)")
    took, _ = runner.run("real-calibrate", ["calibrate", real_dir, "--semantics", "none", "--out",
                                            real_dir / "calibration", "--force"] + threads, ok_codes=(0, 3))
    real_summary = summarise_calibration(json.loads((real_dir / "calibration/evaluation.json").read_text()))
    print(f"      {took:.0f} s: {len(real_summary['placed'])} of {len(real_summary['cameras'])} cameras placed, "
          f"median pair rotation error {_deg(real_summary['median_pair_rotation_error_deg'])}")

    # 2. The twin on the street.
    twin_rig = work / "twin" / "rig"
    progress(f"placing the twin ({a.placement}, {n_frames} frames {step:g} m apart from {source}"
             + (", with its ego vehicle" if a.ego_vehicle else "") + ")")
    make_rig = ["make-rig", "--type", "file", "--rig-file", real_dir / "rig.json", "--scene", a.scene,
                "--placement", a.placement, "--frames", n_frames, "--step", step, "--frame-interval", interval,
                "--seed", a.seed, "--out", twin_rig, "--force"]
    if a.rig_height is not None:
        make_rig += ["--rig-height", a.rig_height]
    if a.ego_vehicle:
        make_rig.append("--ego-vehicle")
    _, out = runner.run("twin-make-rig", make_rig)
    placed_line = next((line for line in out.splitlines() if line.startswith("placed")), None)
    if placed_line:
        print("      " + placed_line)

    # 3. Each sensor preset: render, calibrate.
    twins = []
    for preset in presets:
        render_dir = work / "twin" / preset
        progress(f"rendering the twin with --sensor {preset}")
        took_render, _ = runner.run(f"twin-{preset}-render", [
            "render", "--scene", a.scene, "--rig", twin_rig / "rig.json", "--frames", twin_rig / "frames.json",
            "--out", render_dir, "--spp", a.spp, "--seed", a.seed, "--sensor", preset, "--force"] + threads)
        print(f"      {took_render:.0f} s")
        progress(f"calibrating the twin's {preset} renders")
        took_cal, _ = runner.run(f"twin-{preset}-calibrate", [
            "calibrate", render_dir, "--semantics", "none", "--out", work / "twin" / f"{preset}-calibration",
            "--force"] + threads, ok_codes=(0, 3))
        summary = summarise_calibration(json.loads((work / "twin" / f"{preset}-calibration/evaluation.json").read_text()))
        print(f"      {took_cal:.0f} s: {len(summary['placed'])} of {len(summary['cameras'])} cameras placed, "
              f"median pair rotation error {_deg(summary['median_pair_rotation_error_deg'])}")
        twins.append({"preset": preset, "summary": summary, "comparison": compare_with_real(real_summary, summary),
                      "render_time_s": took_render, "calibrate_time_s": took_cal})

    # 4. The table.
    suffix = " + ego vehicle" if a.ego_vehicle else ""
    columns = [("real photos", real_summary, None)] + [(f"twin {t['preset']}{suffix}", t["summary"], t["comparison"])
                                                        for t in twins]
    rows = table_rows(columns)
    targets = [targets_line(title, comparison) for title, _, comparison in columns[1:]]
    command = "python3 bench/twin_study.py " + " ".join(sys.argv[1:] if argv is None else argv)
    setting = (f"{a.real.name}: {len(truth['cameras'])} cameras, {n_frames} frames {step:g} m apart ({source}); "
               f"twin placed by {a.placement} in {a.scene.name}" + (", with its ego vehicle" if a.ego_vehicle else "")
               + f", spp {a.spp}, seed {a.seed}; calibrate --semantics none")
    print()
    print(setting)
    print(text_table(rows))
    print(f"twin/real: ok within {TARGET_FACTOR:g}x, off beyond (or a value on one side only)")
    print("\n".join(targets))
    md = (f"{setting}\n\n`{command}`\n\n{markdown_table(rows)}\n\n"
          f"twin/real: *ok* within {TARGET_FACTOR:g}×, *off* beyond (or a value on one side only).\n\n"
          + "".join(f"- {line}\n" for line in targets))
    result = {
        "command": command,
        "real_folder": str(real),
        "scene": str(a.scene),
        "placement": a.placement,
        "ego_vehicle": a.ego_vehicle,
        "path": {"frames": n_frames, "step_m": step, "frame_interval_s": interval, "from": source},
        "spp": a.spp,
        "seed": a.seed,
        "real": real_summary,
        "twins": twins,
    }
    write_atomically(work / "twin_study.json", json.dumps(result, indent=1) + "\n")
    write_atomically(work / "twin_study.md", md)
    print(f"wrote {work / 'twin_study.md'} and {work / 'twin_study.json'}")


if __name__ == "__main__":
    main()
