#!/usr/bin/env python3
"""How an a contrario test would gate camera pairs, against the fixed count the calibrator uses.

    python3 bench/pair_gate_nfa.py DIR [DIR ...]

Reads every <mode>/pairs.json (with the rig.json beside it) under the DIRs: calibrations of
rendered datasets, whose pairs carry the ground-truth overlap. For each distinct pair it takes the
two-view fit's k inliers of n matches (screened-out pairs: the counts their failure reason gives)
and the number of false alarms of an essential matrix with k inliers among n matches, as ORSA
(Moisan and Stival 2004) counts it for the 5-point solver: NFA = 10 (n - 5) C(n, k) C(k, 5)
alpha^(k - 5), alpha = 2 d D / A the share of the image within d = 1 px (the fit's inlier
threshold) of an epipolar line, D the image diagonal and A its area. It prints, for pairs of views
that share nothing (overlap 0) and pairs that share some, how many pass the fixed rule (30 inliers
and 10 % of the matches) and how many an a contrario rule (12 inliers, 10 % of the matches, NFA
below each threshold) would pass. Standard library only.
"""

import argparse
import json
import math
import re
import sys
from pathlib import Path

SAMPLE = 5          # the 5-point solver's sample
SOLUTIONS = 10      # its solutions per sample, at most
THRESHOLD_PX = 1.0  # calibrate's --max-error-px default


def log10_choose(n, k):
    return (math.lgamma(n + 1) - math.lgamma(k + 1) - math.lgamma(n - k + 1)) / math.log(10)


def log10_false_alarms(k, n, width, height):
    if k <= SAMPLE:
        return math.inf
    alpha = 2 * THRESHOLD_PX * math.hypot(width, height) / (width * height)
    return (math.log10(SOLUTIONS) + math.log10(max(n - SAMPLE, 1)) + log10_choose(n, k) +
            log10_choose(k, SAMPLE) + (k - SAMPLE) * math.log10(alpha))


def pairs_of(dirs):
    """(overlap, k, n, log10 NFA) per distinct pair of the calibrations under `dirs`."""
    seen = set()
    for d in dirs:
        for path in sorted(Path(d).rglob("pairs.json")):
            rig_path = path.parent / "rig.json"
            if not rig_path.exists():
                continue
            size = {c["name"]: (c["width"], c["height"]) for c in json.loads(rig_path.read_text())["cameras"]}
            for p in json.loads(path.read_text())["pairs"]:
                if p.get("overlap") is None:
                    continue
                counted = re.search(r"(\d+) inliers of (\d+) matches", p.get("failure_reason", ""))
                if counted:
                    k, n = int(counted.group(1)), int(counted.group(2))
                elif p["success"]:
                    k, n = p["inliers"], p["matches"]
                else:
                    continue
                width, height = size[p["cam_a"]]
                key = (p["cam_a"], p["cam_b"], k, n, width, height)
                if key in seen:  # the same pair of the same images, calibrated again
                    continue
                seen.add(key)
                yield p["overlap"], k, n, log10_false_alarms(k, n, width, height)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("dirs", nargs="+", type=Path)
    a = ap.parse_args()
    rows = list(pairs_of(a.dirs))
    if not rows:
        sys.exit("pair_gate_nfa: no pairs.json with ground-truth overlap under " + ", ".join(map(str, a.dirs)))
    apart = [r for r in rows if r[0] == 0]
    sharing = [r for r in rows if r[0] > 0]
    fixed = lambda r: r[1] >= 30 and r[1] >= 0.1 * r[2]
    print(f"{len(rows)} distinct pairs: {len(apart)} of views that share nothing, {len(sharing)} that share some")
    print(f"{'rule':<34}{'share nothing, passed':>24}{'share some, passed':>22}")
    print(f"{'30 inliers and 10 % (calibrate)':<34}{sum(map(fixed, apart)):>24}{sum(map(fixed, sharing)):>22}")
    for t in (-3, -6, -9, -12, -15):
        rule = lambda r: r[1] >= 12 and r[1] >= 0.1 * r[2] and r[3] < t
        print(f"{'12 inliers, 10 %, NFA < 1e' + str(t):<34}{sum(map(rule, apart)):>24}{sum(map(rule, sharing)):>22}")
    worst = sorted((r for r in apart if r[1] >= 12 and r[1] >= 0.1 * r[2]), key=lambda r: r[3])[:5]
    print("views that share nothing, the most significant: " +
          "; ".join(f"{k} of {n} matches, NFA 1e{nfa:.1f}" for _, k, n, nfa in worst))


if __name__ == "__main__":
    main()
