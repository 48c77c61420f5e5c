#!/usr/bin/env python3
"""Calibrate a real-rig folder with rigsim, COLMAP 3.8 and COLMAP >= 4 one after the other, and score each against its truth.

    python3 bench/real_rigs/peers.py FOLDER [--rigsim build/apps/rigsim/rigsim] [--work /tmp/real-rigs-peers]
        [--colmap colmap] [--colmap4 PATH | --colmap4 none] [--threads 2] [--sequential] [--json OUT]

FOLDER is a real-rig folder (images/<cam>/<frame>.<ext>, rig.json with each camera's intrinsics,
truth_rig.json), as bench/real_rigs/prepare_*.py write them and ../shared/data/ddad-scene01 is.
Nothing is written into FOLDER; everything goes to WORK/<folder name>/. The methods:

  rigsim            `rigsim calibrate FOLDER --semantics none`
  colmap3.8         COLMAP as rigsim's sweep peer runs it (evaluation/colmap_peer.h): feature_extractor
                    once per camera with its intrinsics from rig.json (cx, cy + 0.5: COLMAP's pixel
                    centres are at .5), exhaustive_matcher, mapper with the intrinsics held
  colmap4           COLMAP >= 4 (--colmap4, else the newest build in bench/colmap4/build.sh's cache),
                    the same steps: extraction per camera with the intrinsics, exhaustive matching,
                    mapper with the intrinsics held (each camera its own rig)
  colmap4-rig       COLMAP 4's rig workflow for unknown sensor poses: rig_configurator with a rig
                    config from rig.json (first camera the reference, no cam_from_rig) and the
                    colmap4 model as input, which sets each sensor_from_rig to the mean of the
                    registered frames; then the mapper again from the same matches with the rig,
                    refining sensor_from_rig (--Mapper.ba_refine_sensor_from_rig 1)
  colmap4-global    rig_configurator with the same config and no model (sensor_from_rig unknown),
                    then global_mapper, which estimates sensor_from_rig by rotation averaging and
                    refines it in its bundle adjustment
  colmap4-global-seq  (--sequential) as colmap4-global, but the rig configured before matching
                    and sequential_matcher pairing each frame's images with each other and with
                    the next frames' (SequentialMatching.expand_rig_images) instead of every pair

Each is scored by `rigsim evaluate ESTIMATE --truth WORK/<name>/truth_rig.json` (a calibration
folder, or a COLMAP text model: its largest sub-model, cam_from_rig from the images of the frames
where the reference camera is registered; gauge and scale aligned as for renders). Prints one
table of the cameras' rotation / centre-direction errors and one of the wall times per step, and
writes both as JSON (WORK/<name>/peers.json, or --json). A COLMAP step that fails (the mapper finds
no initial pair, say) ends its method with the reason; the others still run. Exit code 0 when
the tables are written (whatever each method did), 1 on bad input or a missing program.

Never part of the test suite: it needs real photos and a COLMAP >= 4 build (bench/colmap4/build.sh).
Standard library only.
"""

import argparse
import glob
import json
import os
import re
import shutil
import sqlite3
import subprocess
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from rig_common import truth_rig_json  # noqa: E402

IMAGE_EXTENSIONS = {".png", ".jpg", ".jpeg", ".bmp", ".tif", ".tiff"}
# rigsim's camera models take their parameters in COLMAP's order under the same names.
COLMAP_MODELS = {"PINHOLE", "OPENCV", "FULL_OPENCV", "OPENCV_FISHEYE"}


def fail(message):
    print(f"peers.py: error: {message}", file=sys.stderr)
    sys.exit(1)


def which(program):
    """The program's path: as given when it names a file, else found on the PATH; None when neither."""
    if os.sep in program:
        return os.path.abspath(program) if os.access(program, os.X_OK) else None
    return shutil.which(program)


def colmap4_from_cache():
    """The newest COLMAP >= 4 that bench/colmap4/build.sh left in its cache, or None."""
    cache = Path(os.environ.get("RIGSIM_COLMAP_CACHE", Path.home() / ".cache" / "rigsim"))
    best = None
    for binary in glob.glob(str(cache / "colmap-*" / "bin" / "colmap")):
        m = re.match(r"colmap-(\d+)\.(\d+)(?:\.(\d+))?$", Path(binary).parent.parent.name)
        if not m or int(m.group(1)) < 4 or not os.access(binary, os.X_OK):
            continue
        version = tuple(int(g or 0) for g in m.groups())
        if best is None or version > best[0]:
            best = (version, binary)
    return best[1] if best else None


def read_folder(folder):
    """(cameras from rig.json, {camera name: sorted image names 'cam/file'}); stops naming the problem."""
    rig_path = folder / "rig.json"
    try:
        cameras = json.loads(rig_path.read_text())["cameras"]
    except (OSError, ValueError, KeyError, TypeError) as e:
        fail(f"{rig_path}: not a rig file with a 'cameras' list ({e})")
    images = {}
    for cam in cameras:
        name = cam.get("name")
        if cam.get("model") not in COLMAP_MODELS:
            fail(f"{rig_path}: camera {name}: model {cam.get('model')!r} is not one COLMAP takes "
                 f"({', '.join(sorted(COLMAP_MODELS))})")
        if not isinstance(cam.get("params"), list) or len(cam["params"]) < 4:
            fail(f"{rig_path}: camera {name}: no intrinsics ('params' with fx, fy, cx, cy first)")
        d = folder / "images" / name
        files = sorted(p.name for p in d.iterdir() if p.suffix.lower() in IMAGE_EXTENSIONS) if d.is_dir() else []
        if not files:
            fail(f"{d}: no images of camera {name}")
        images[name] = [f"{name}/{f}" for f in files]
    return cameras, images


class Method:
    """One method's steps (name, wall seconds) and how it ended."""

    def __init__(self, name, program=None):
        self.name = name
        self.program = program
        self.steps = []
        self.failure = None
        self.estimate = None
        self.scores = None

    def total(self):
        return sum(s for _, s in self.steps)


def log_errors(log, count=2):
    """The last COUNT error lines of a COLMAP log (glog's E/F lines, 'ERROR', a model discarded, an exception's
    what()), colours removed, else its last lines."""
    lines = [re.sub(r"\x1b\[[0-9;]*m", "", line).strip() for line in open(log, errors="replace")]
    lines = [line for line in lines if line]
    errors = [line for line in lines if re.match(r"[EF]\d{8} ", line) or
              any(k in line for k in ("ERROR", "Discarding", "what():", "Check failed"))]
    return [re.sub(r"^[EFWI]\d{8} [\d:.]+ +\d+ ", "", line) for line in (errors or lines)[-count:]]


def run_step(method, step, args, log, ok_codes=(0,)):
    """Runs one step, logging to LOG, timing it into METHOD; False (with method.failure) when it fails."""
    start = time.monotonic()
    with open(log, "w") as out:
        out.write("$ " + " ".join(str(a) for a in args) + "\n")
        out.flush()
        try:
            rc = subprocess.run([str(a) for a in args], stdout=out, stderr=subprocess.STDOUT).returncode
        except OSError as e:
            rc, out_error = None, str(e)
    method.steps.append((step, time.monotonic() - start))
    if rc in ok_codes:
        return True
    if rc is None:
        method.failure = f"{step}: {out_error}"
    else:
        method.failure = f"{step} exited with {rc}: " + " | ".join(log_errors(log))
    return False


def colmap_params(cam):
    p = [float(v) for v in cam["params"]]
    p[2] += 0.5  # COLMAP's pixel centres are at .5, rigsim's (and OpenCV's) at integers
    p[3] += 0.5
    return ",".join(repr(v) for v in p)


def extract(method, colmap, v4, work, folder, cameras, images, threads):
    """feature_extractor once per camera, its images listed and its intrinsics given (held later)."""
    prefix = "FeatureExtraction" if v4 else "SiftExtraction"
    lists = work / "lists"
    lists.mkdir(parents=True, exist_ok=True)
    start_steps = len(method.steps)
    for cam in cameras:
        lst = lists / f"{cam['name']}.txt"
        lst.write_text("\n".join(images[cam["name"]]) + "\n")
        if not run_step(method, f"extract {cam['name']}",
                        [colmap, "feature_extractor", "--database_path", work / "database.db",
                         "--image_path", folder / "images", "--image_list_path", lst,
                         "--ImageReader.single_camera", "1", "--ImageReader.camera_model", cam["model"],
                         "--ImageReader.camera_params", colmap_params(cam), f"--{prefix}.use_gpu", "0",
                         f"--{prefix}.num_threads", threads],
                        work / f"extract_{cam['name']}.log"):
            return False
    # One "extract" step in the tables, the per-camera runs summed.
    seconds = sum(s for _, s in method.steps[start_steps:])
    del method.steps[start_steps:]
    method.steps.append(("extract", seconds))
    return True


def match(method, colmap, v4, work, kind, threads):
    prefix = "FeatureMatching" if v4 else "SiftMatching"
    args = [colmap, f"{kind}_matcher", "--database_path", work / "database.db", f"--{prefix}.use_gpu", "0",
            f"--{prefix}.num_threads", threads]
    if kind == "sequential":
        args += ["--SequentialMatching.expand_rig_images", "1"]
    return run_step(method, f"{kind} match", args, work / f"{kind}_match.log")


def to_text(method, colmap, sparse, work):
    """Each sub-model of SPARSE converted to text in place (what rigsim evaluate reads)."""
    subs = [p for p in sorted(sparse.iterdir()) if p.is_dir()] if sparse.is_dir() else []
    if not subs:
        method.failure = f"no model in {sparse}"
        return False
    start = time.monotonic()
    for sub in subs:
        if subprocess.run([str(colmap), "model_converter", "--input_path", str(sub), "--output_path", str(sub),
                           "--output_type", "TXT"], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL).returncode:
            method.failure = f"model_converter failed on {sub}"
            return False
    method.steps.append(("to text", time.monotonic() - start))
    method.estimate = sparse
    return True


def mapper(method, colmap, work, folder, database, sparse, threads, init_min_tri_angle, rig=False):
    sparse.mkdir(parents=True, exist_ok=True)
    args = [colmap, "mapper", "--database_path", database, "--image_path", folder / "images", "--output_path", sparse,
            "--Mapper.ba_refine_focal_length", "0", "--Mapper.ba_refine_principal_point", "0",
            "--Mapper.ba_refine_extra_params", "0", "--Mapper.num_threads", threads]
    if init_min_tri_angle is not None:
        args += ["--Mapper.init_min_tri_angle", repr(init_min_tri_angle)]
    if rig:
        args += ["--Mapper.ba_refine_sensor_from_rig", "1"]
    return run_step(method, "rig mapper" if rig else "mapper", args, work / f"{sparse.name}_mapper.log")


def largest_model(sparse):
    """The sub-model of SPARSE with the most registered images (by images.bin's count)."""
    best, best_n = None, -1
    for sub in sorted(p for p in sparse.iterdir() if p.is_dir()):
        f = sub / "images.bin"
        if f.is_file():
            n = int.from_bytes(f.read_bytes()[:8], "little")
            if n > best_n:
                best, best_n = sub, n
    return best


def rig_config(cameras):
    """COLMAP's rig config: one rig, the first camera the reference, no cam_from_rig (to be estimated)."""
    return [{"cameras": [dict({"image_prefix": f"{c['name']}/"}, **({"ref_sensor": True} if i == 0 else {}))
                         for i, c in enumerate(cameras)]}]


def copy_database(src, dst):
    """A copy of a COLMAP database (sqlite's own backup, so that no journal is left half copied)."""
    if dst.exists():
        dst.unlink()
    with sqlite3.connect(src) as a, sqlite3.connect(dst) as b:
        a.backup(b)


def run_colmap38(colmap, work, folder, cameras, images, threads, init_angle):
    m = Method("colmap3.8", colmap)
    work.mkdir(parents=True)
    if (extract(m, colmap, False, work, folder, cameras, images, threads) and
            match(m, colmap, False, work, "exhaustive", threads) and
            mapper(m, colmap, work, folder, work / "database.db", work / "sparse", threads, init_angle)):
        to_text(m, colmap, work / "sparse", work)
    return m


def run_colmap4(colmap, work, folder, cameras, images, threads, sequential, init_angle):
    """The colmap4, colmap4-rig, colmap4-global (and colmap4-global-seq) methods; shared steps are
    run once and counted in each method that uses them."""
    work.mkdir(parents=True)
    config = work / "rig_config.json"
    config.write_text(json.dumps(rig_config(cameras), indent=1) + "\n")
    plain, rig, glob_ = Method("colmap4", colmap), Method("colmap4-rig", colmap), Method("colmap4-global", colmap)
    methods = [plain, rig, glob_]
    shared = Method("shared")
    extracted = extract(shared, colmap, True, work, folder, cameras, images, threads)
    if extracted:
        copy_database(work / "database.db", work / "extracted.db")
        match(shared, colmap, True, work, "exhaustive", threads)
    for m in methods:
        m.steps = list(shared.steps)
        m.failure = shared.failure
    if shared.failure:
        return methods + ([Method("colmap4-global-seq", colmap)] if sequential else [])

    if mapper(plain, colmap, work, folder, work / "database.db", work / "sparse", threads, init_angle):
        to_text(plain, colmap, work / "sparse", work)

    rig.steps += [s for s in plain.steps if s[0] == "mapper"]
    if plain.failure:
        rig.failure = f"needs the colmap4 model, which failed ({plain.failure})"
    else:
        copy_database(work / "database.db", work / "rig.db")
        model = largest_model(work / "sparse")
        (work / "rig_start").mkdir(exist_ok=True)
        if (run_step(rig, "rig_configurator",
                     [colmap, "rig_configurator", "--database_path", work / "rig.db", "--rig_config_path", config,
                      "--input_path", model, "--output_path", work / "rig_start"], work / "rig_configurator.log") and
                mapper(rig, colmap, work, folder, work / "rig.db", work / "sparse_rig", threads, init_angle, rig=True)):
            to_text(rig, colmap, work / "sparse_rig", work)

    def global_mapper(m, database, sparse):
        sparse.mkdir(parents=True, exist_ok=True)
        return run_step(m, "global_mapper",
                        [colmap, "global_mapper", "--database_path", database, "--image_path", folder / "images",
                         "--output_path", sparse, "--GlobalMapper.ba_refine_focal_length", "0",
                         "--GlobalMapper.ba_refine_principal_point", "0", "--GlobalMapper.ba_refine_extra_params", "0",
                         "--GlobalMapper.refine_sensor_from_rig", "1", "--GlobalMapper.num_threads", threads],
                        work / f"{sparse.name}_global_mapper.log")

    copy_database(work / "database.db", work / "global.db")
    if (run_step(glob_, "rig_configurator",
                 [colmap, "rig_configurator", "--database_path", work / "global.db", "--rig_config_path", config],
                 work / "rig_configurator_global.log") and
            global_mapper(glob_, work / "global.db", work / "sparse_global")):
        to_text(glob_, colmap, work / "sparse_global", work)

    if sequential:
        seq = Method("colmap4-global-seq", colmap)
        seq.steps = [s for s in shared.steps if s[0] == "extract"]
        methods.append(seq)
        seq_work = work / "sequential"
        seq_work.mkdir()
        copy_database(work / "extracted.db", seq_work / "database.db")
        if (run_step(seq, "rig_configurator",
                     [colmap, "rig_configurator", "--database_path", seq_work / "database.db", "--rig_config_path",
                      config], seq_work / "rig_configurator.log") and
                match(seq, colmap, True, seq_work, "sequential", threads) and
                global_mapper(seq, seq_work / "database.db", seq_work / "sparse_global")):
            to_text(seq, colmap, seq_work / "sparse_global", seq_work)
    return methods


def run_rigsim(rigsim, work, folder, threads):
    m = Method("rigsim", rigsim)
    work.mkdir(parents=True)
    calib = work / "calibration"
    if run_step(m, "calibrate", [rigsim, "calibrate", folder, "--semantics", "none", "--out", calib, "--force",
                                 "--threads", threads], work.parent / "rigsim_calibrate.log", ok_codes=(0, 3)):
        m.estimate = calib
    return m


def score(method, rigsim, truth, work):
    """rigsim evaluate's per-camera scores of the method's estimate (None when it made none)."""
    if method.estimate is None:
        return
    out = work / f"evaluate_{method.name}.json"
    args = [rigsim, "evaluate", method.estimate, "--truth", truth, "--json", out, "--force"]
    with open(work / f"evaluate_{method.name}.log", "w") as log:
        rc = subprocess.run([str(a) for a in args], stdout=log, stderr=subprocess.STDOUT).returncode
    if rc != 0:
        method.failure = f"rigsim evaluate exited with {rc} (see {work / f'evaluate_{method.name}.log'})"
        return
    ev = json.loads(out.read_text())
    scored = next(iter(ev["methods"].values()))
    method.scores = {"cameras": scored["cameras"], "notes": scored.get("notes", [])}


def cell(cam):
    if cam is None or not cam.get("has_rotation"):
        return "-"
    rot = f"{cam['rotation_error_deg']:.2f}°"
    d = cam.get("translation_direction_error_deg")
    if not cam.get("posed"):
        return f"{rot} / rot. only"
    return f"{rot} / {d:.1f}°" if d is not None else f"{rot} / ref"


def report(methods, names):
    lines = ["| method | placed | " + " | ".join(names) + " | total |",
             "|---|---|" + "---:|" * len(names) + "---:|"]
    for m in methods:
        cams = {c["name"]: c for c in (m.scores or {}).get("cameras", [])}
        placed = sum(1 for c in cams.values() if c.get("posed"))
        lines.append(f"| {m.name} | {placed} of {len(names)} | " +
                     " | ".join(cell(cams.get(n)) for n in names) + f" | {m.total():.1f} s |")
    lines.append("")
    lines.append("| method | wall time per step |")
    lines.append("|---|---|")
    for m in methods:
        steps = ", ".join(f"{n} {s:.1f} s" for n, s in m.steps)
        lines.append(f"| {m.name} | {steps} |")
    notes = []
    for m in methods:
        if m.failure:
            notes.append(f"{m.name}: {m.failure}")
        for n in (m.scores or {}).get("notes", []):
            notes.append(f"{m.name}: {n}")
    return "\n".join(lines), notes


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0], epilog=__doc__.split("\n\n", 2)[2],
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("folder", type=Path, help="real-rig folder: images/<cam>/, rig.json, truth_rig.json")
    ap.add_argument("--rigsim", default="build/apps/rigsim/rigsim", help="rigsim binary (calibrate and evaluate)")
    ap.add_argument("--work", type=Path, default=Path("/tmp/real-rigs-peers"),
                    help="work folder; WORK/<folder name>/ is replaced")
    ap.add_argument("--colmap", default="colmap", help="COLMAP 3.8 (Debian's); 'none' skips it")
    ap.add_argument("--colmap4", default=None,
                    help="COLMAP >= 4 binary (default: the newest in bench/colmap4/build.sh's cache, "
                         "$RIGSIM_COLMAP_CACHE or ~/.cache/rigsim); 'none' skips it")
    ap.add_argument("--threads", type=int, default=2, help="threads of every method (default 2)")
    ap.add_argument("--sequential", action="store_true",
                    help="also colmap4-global-seq: the rig configured before matching, rig-expanded sequential "
                         "matching instead of exhaustive")
    ap.add_argument("--init-min-tri-angle", type=float, metavar="DEG",
                    help="the incremental mappers' Mapper.init_min_tri_angle (COLMAP's default, 16, when not given; "
                         "it halves it as it relaxes the search for an initial pair)")
    ap.add_argument("--json", type=Path, help="where to write the tables as JSON (default WORK/<name>/peers.json)")
    a = ap.parse_args()

    folder = a.folder.resolve()
    if not folder.is_dir():
        fail(f"{a.folder}: no such folder")
    cameras, images = read_folder(folder)
    truth = truth_rig_json(folder)
    rigsim = which(a.rigsim) or fail(f"{a.rigsim}: no such program (--rigsim)")
    colmap = None
    if a.colmap != "none":
        colmap = which(a.colmap) or fail(f"{a.colmap}: no such program (--colmap; 'none' skips COLMAP 3.8)")
    colmap4 = None
    if a.colmap4 != "none":
        colmap4 = which(a.colmap4) if a.colmap4 else colmap4_from_cache()
        if a.colmap4 and not colmap4:
            fail(f"{a.colmap4}: no such program (--colmap4; 'none' skips COLMAP 4)")
        if not colmap4:
            print("peers.py: no COLMAP >= 4 given or in the cache (bench/colmap4/build.sh builds one): skipping it",
                  file=sys.stderr)
    threads = str(a.threads)

    work = (a.work / folder.name).resolve()
    if work.exists():
        shutil.rmtree(work)
    work.mkdir(parents=True)
    truth_path = work / "truth_rig.json"
    truth_path.write_text(json.dumps(truth, indent=1) + "\n")
    names = [c["name"] for c in truth["cameras"]]

    methods = []
    print(f"rigsim calibrate ({rigsim}) ...", flush=True)
    methods.append(run_rigsim(rigsim, work / "rigsim", folder, threads))
    if colmap:
        print(f"COLMAP 3.8 ({colmap}) ...", flush=True)
        methods.append(run_colmap38(colmap, work / "colmap3.8", folder, cameras, images, threads,
                                    a.init_min_tri_angle))
    if colmap4:
        print(f"COLMAP 4 ({colmap4}) ...", flush=True)
        methods += run_colmap4(colmap4, work / "colmap4", folder, cameras, images, threads, a.sequential,
                               a.init_min_tri_angle)
    for m in methods:
        score(m, rigsim, truth_path, work)

    table, notes = report(methods, names)
    print(f"\n{folder.name}: rotation / centre-direction error per camera after the gauge is aligned "
          f"(rigsim evaluate --truth), first camera the reference\n")
    print(table)
    for n in notes:
        print(f"  {n}")
    result = {
        "folder": str(folder),
        "threads": a.threads,
        "init_min_tri_angle": a.init_min_tri_angle,
        "cameras": names,
        "methods": [{"name": m.name, "program": str(m.program) if m.program else None,
                     "failure": m.failure, "estimate": str(m.estimate) if m.estimate else None,
                     "steps": [{"step": n, "seconds": round(s, 3)} for n, s in m.steps],
                     "total_seconds": round(m.total(), 3),
                     "placed": sum(1 for c in (m.scores or {}).get("cameras", []) if c.get("posed")),
                     "cameras": (m.scores or {}).get("cameras", []),
                     "notes": (m.scores or {}).get("notes", [])} for m in methods],
    }
    out = a.json or work / "peers.json"
    tmp = out.with_name(out.name + ".tmp")
    tmp.write_text(json.dumps(result, indent=1) + "\n")
    os.replace(tmp, out)
    print(f"\ntables written to {out}; logs and models in {work}")


if __name__ == "__main__":
    main()
