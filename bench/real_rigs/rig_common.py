"""Shared helpers of the real-rig converters (prepare_*.py): rigid transforms and the output folder.

A rigid transform a_from_b is a pair (q, t): q a unit quaternion [w, x, y, z] (Hamilton, active),
t a 3-vector, so that x_a = R(q) x_b + t. The output folder is the layout of
../shared/data/ddad-scene01 (what `rigsim calibrate` reads for real photos):

    OUT/rig.json          cameras with intrinsics only (what a user gives calibrate)
    OUT/truth_rig.json    the same cameras with cam_from_rig {"rotation": [w,x,y,z], "translation"}
                          (rig frame = the first camera)
    OUT/images/<cam>/<frame>.<ext>
    OUT/README.md

Standard library only.
"""

import json
import math
import shutil
import subprocess
from pathlib import Path


def git_commit(src):
    """The checkout's commit, for a README; says so when SRC is not a git checkout."""
    try:
        return subprocess.run(["git", "-C", str(src), "rev-parse", "HEAD"], capture_output=True, text=True,
                              check=True).stdout.strip()
    except (OSError, subprocess.CalledProcessError):
        return "unknown (not a git checkout)"


def q_normalize(q):
    n = math.sqrt(sum(c * c for c in q))
    q = [c / n for c in q]
    return q if q[0] >= 0 else [-c for c in q]


def q_mul(a, b):
    aw, ax, ay, az = a
    bw, bx, by, bz = b
    return [aw * bw - ax * bx - ay * by - az * bz,
            aw * bx + ax * bw + ay * bz - az * by,
            aw * by - ax * bz + ay * bw + az * bx,
            aw * bz + ax * by - ay * bx + az * bw]


def q_conj(q):
    return [q[0], -q[1], -q[2], -q[3]]


def q_rotate(q, v):
    p = q_mul(q_mul(q, [0.0, v[0], v[1], v[2]]), q_conj(q))
    return p[1:]


def q_to_matrix(q):
    w, x, y, z = q_normalize(q)
    return [[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
            [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
            [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]]


def q_from_matrix(m):
    """Unit quaternion [w, x, y, z] of a 3x3 rotation matrix (rows), Shepperd's method."""
    tr = m[0][0] + m[1][1] + m[2][2]
    if tr > 0:
        s = math.sqrt(tr + 1.0) * 2
        q = [0.25 * s, (m[2][1] - m[1][2]) / s, (m[0][2] - m[2][0]) / s, (m[1][0] - m[0][1]) / s]
    elif m[0][0] > m[1][1] and m[0][0] > m[2][2]:
        s = math.sqrt(1.0 + m[0][0] - m[1][1] - m[2][2]) * 2
        q = [(m[2][1] - m[1][2]) / s, 0.25 * s, (m[0][1] + m[1][0]) / s, (m[0][2] + m[2][0]) / s]
    elif m[1][1] > m[2][2]:
        s = math.sqrt(1.0 + m[1][1] - m[0][0] - m[2][2]) * 2
        q = [(m[0][2] - m[2][0]) / s, (m[0][1] + m[1][0]) / s, 0.25 * s, (m[1][2] + m[2][1]) / s]
    else:
        s = math.sqrt(1.0 + m[2][2] - m[0][0] - m[1][1]) * 2
        q = [(m[1][0] - m[0][1]) / s, (m[0][2] + m[2][0]) / s, (m[1][2] + m[2][1]) / s, 0.25 * s]
    return q_normalize(q)


def compose(a_from_b, b_from_c):
    qa, ta = a_from_b
    qb, tb = b_from_c
    r = q_rotate(qa, tb)
    return q_normalize(q_mul(qa, qb)), [r[0] + ta[0], r[1] + ta[1], r[2] + ta[2]]


def inverse(a_from_b):
    q, t = a_from_b
    qi = q_conj(q)
    r = q_rotate(qi, t)
    return q_normalize(qi), [-r[0], -r[1], -r[2]]


def angle_deg(q):
    """Rotation angle of a unit quaternion, degrees."""
    w = min(1.0, abs(q_normalize(q)[0]))
    return math.degrees(2 * math.acos(w))


def rotation_between_deg(qa, qb):
    return angle_deg(q_mul(q_conj(qa), qb))


def norm(v):
    return math.sqrt(sum(c * c for c in v))


def vector_angle_deg(a, b):
    na, nb = norm(a), norm(b)
    if na == 0 or nb == 0:
        return float("nan")
    c = sum(x * y for x, y in zip(a, b)) / (na * nb)
    return math.degrees(math.acos(max(-1.0, min(1.0, c))))


def view_direction(cam_from_rig):
    """The camera's optical axis (+z of the camera) in the rig frame."""
    return q_rotate(q_conj(cam_from_rig[0]), [0.0, 0.0, 1.0])


def centre_in_rig(cam_from_rig):
    return inverse(cam_from_rig)[1]


def clean(x, digits=12):
    """Round tiny numerical noise so that the identity prints as the identity."""
    return [0.0 if abs(c) < 10 ** -digits else c for c in x]


def write_folder(out, cameras, images, readme, force=False):
    """Write the dataset folder.

    cameras: list of dicts name, model, width, height, params, cam_from_rig (q, t), rig frame = first.
    images: dict camera name -> list of (frame name, source Path); every camera has every frame.
    """
    out = Path(out)
    if out.exists():
        if not force:
            raise SystemExit(f"{out} exists; pass --force to replace it")
        shutil.rmtree(out)
    frames = [f for f, _ in images[cameras[0]["name"]]]
    for cam in cameras:
        got = [f for f, _ in images[cam["name"]]]
        if got != frames:
            raise SystemExit(f"camera {cam['name']} has frames {got}, the first camera {frames}")
    (out / "images").mkdir(parents=True)
    rig, truth = {"cameras": []}, {"cameras": []}
    for cam in cameras:
        intr = {k: cam[k] for k in ("name", "model", "width", "height", "params")}
        rig["cameras"].append(dict(intr))
        q, t = cam["cam_from_rig"]
        truth["cameras"].append(dict(intr, cam_from_rig={"rotation": clean(q_normalize(q)),
                                                         "translation": clean(t)}))
        d = out / "images" / cam["name"]
        d.mkdir()
        for frame, src in images[cam["name"]]:
            shutil.copyfile(src, d / (frame + Path(src).suffix.lower()))
    (out / "rig.json").write_text(json.dumps(rig, indent=1) + "\n")
    (out / "truth_rig.json").write_text(json.dumps(truth, indent=1) + "\n")
    (out / "README.md").write_text(readme)


def truth_rig_json(folder):
    """The folder's rig with its truth as rigsim reads a rig.json (make-rig --rig-file, calibrate).

    truth_rig.json names each cam_from_rig rotation "rotation"; rig.json's key is "rotation_wxyz".
    A folder without truth_rig.json gives its rig.json when every camera there has a cam_from_rig.
    Anything else stops with a message naming the file and what is missing.
    """
    folder = Path(folder)
    path = folder / "truth_rig.json"
    if not path.is_file():
        path = folder / "rig.json"
        if not path.is_file():
            raise SystemExit(f"{folder}: neither truth_rig.json nor rig.json: no rig to compare with")
    try:
        rig = json.loads(path.read_text())
        cameras = rig["cameras"]
    except (OSError, ValueError, KeyError, TypeError) as e:
        raise SystemExit(f"{path}: not a rig file with a 'cameras' list ({e})")
    if not isinstance(cameras, list) or not cameras:
        raise SystemExit(f"{path}: no cameras")
    for cam in cameras:
        pose = cam.get("cam_from_rig") if isinstance(cam, dict) else None
        if not isinstance(pose, dict) or not ({"rotation", "rotation_wxyz"} & pose.keys()) or "translation" not in pose:
            name = cam.get("name", "?") if isinstance(cam, dict) else "?"
            raise SystemExit(f"{path}: camera {name} has no cam_from_rig (rotation and translation): "
                             "the rig's truth is needed (truth_rig.json, as prepare_*.py write it)")
        if "rotation" in pose:
            pose["rotation_wxyz"] = pose.pop("rotation")
    return rig


def describe_rig(cameras):
    """Lines describing each camera in the rig frame (view direction, centre, baseline to the first)."""
    lines = []
    for cam in cameras:
        d = view_direction(cam["cam_from_rig"])
        c = centre_in_rig(cam["cam_from_rig"])
        yaw = math.degrees(math.atan2(d[0], d[2]))
        lines.append(f"{cam['name']}: view direction in rig frame ({d[0]:+.3f}, {d[1]:+.3f}, {d[2]:+.3f}) "
                     f"= {yaw:+.1f} deg about the first camera's y axis, centre ({c[0]:+.3f}, {c[1]:+.3f}, "
                     f"{c[2]:+.3f}) m, {norm(c):.3f} m from the first, rotation {angle_deg(cam['cam_from_rig'][0]):.2f} deg")
    return lines
