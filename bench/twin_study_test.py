#!/usr/bin/env python3
"""The twin study's figures (bench/twin_study.py) on made-up calibrations: what is counted, the
ratios and their 2x targets, the table. Runs without rigsim or any data (ctest twin_study_test)."""

import sys
import unittest
from pathlib import Path

sys.dont_write_bytecode = True
sys.path.insert(0, str(Path(__file__).resolve().parent))
import twin_study as ts  # noqa: E402


def pair(a, b, matches, inliers=0, rot=None, kind="general", success=True, reason=""):
    return {"cam_a": a, "cam_b": b, "matches": matches, "inliers": inliers,
            "within_tolerance": rot is not None and rot <= 2.0,
            "inlier_ratio": inliers / matches if success and matches else None,
            "rotation_error_deg": rot, "pair_type": kind, "success": success, "failure_reason": reason}


def evaluation(pairs, cameras):
    """An evaluation.json of one mode: cameras as (name, calibrated, has a rotation)."""
    cams = [{"name": n, "calibrated": c, "rotation_wxyz": [1, 0, 0, 0] if r else None} for n, c, r in cameras]
    return {"methods": {"none": {"pairs": pairs, "rig": {"cameras": cams}}}}


REAL = evaluation([pair("A", "B", 1000, 400, 0.1, "rotation-only"),
                   pair("A", "C", 800, 300, 3.0),
                   pair("B", "C", 0, success=False, reason="screened out (no shared view)"),
                   pair("A", "A", 500, 450, 0.01)],  # a camera with itself across frames: not a camera pair
                  [("A", True, True), ("B", False, True), ("C", False, False)])


class SummariseTest(unittest.TestCase):
    def test_counts_camera_pairs_and_the_solved_median(self):
        s = ts.summarise_calibration(REAL)
        self.assertEqual(list(s["pairs"]), ["A-B", "A-C", "B-C"])
        self.assertEqual(s["placed"], ["A"])
        self.assertEqual(s["rotation_only"], ["B"])
        self.assertEqual(s["solved_pairs"], 2)
        self.assertAlmostEqual(s["median_pair_rotation_error_deg"], 1.55)
        self.assertEqual(s["pairs"]["A-B"]["fit"], "rotation-only")
        self.assertEqual(s["pairs"]["A-C"]["fit"], "general, beyond tolerance")
        self.assertEqual(s["pairs"]["B-C"]["fit"], "screened out")
        self.assertIsNone(s["pairs"]["B-C"]["inlier_ratio"])
        self.assertAlmostEqual(s["pairs"]["A-C"]["inlier_ratio"], 0.375)

    def test_a_failed_pair_has_no_rotation_error_or_inliers(self):
        ev = evaluation([pair("A", "B", 300, 20, 40.0, success=False, reason="too few inliers")],
                        [("A", True, True), ("B", False, False)])
        s = ts.summarise_calibration(ev)
        self.assertEqual(s["pairs"]["A-B"]["fit"], "not solved")
        self.assertIsNone(s["pairs"]["A-B"]["rotation_error_deg"])
        self.assertEqual(s["pairs"]["A-B"]["inliers"], 0)
        self.assertIsNone(s["median_pair_rotation_error_deg"])


class RatioTest(unittest.TestCase):
    def test_within_two_either_way_inclusive(self):
        self.assertEqual(ts.ratio_against(20, 10), {"ratio": 2.0, "within": True})
        self.assertEqual(ts.ratio_against(5, 10), {"ratio": 0.5, "within": True})
        self.assertFalse(ts.ratio_against(20.1, 10)["within"])
        self.assertFalse(ts.ratio_against(4.9, 10)["within"])

    def test_missing_and_zero_values(self):
        self.assertEqual(ts.ratio_against(None, None), {"ratio": None, "within": True})
        self.assertEqual(ts.ratio_against(0, 0), {"ratio": None, "within": True})
        self.assertFalse(ts.ratio_against(None, 0.3)["within"])
        self.assertFalse(ts.ratio_against(0.3, None)["within"])
        self.assertFalse(ts.ratio_against(5, 0)["within"])
        self.assertEqual(ts.ratio_against(0, 5), {"ratio": 0.0, "within": False})


class CompareTest(unittest.TestCase):
    def setUp(self):
        self.real = ts.summarise_calibration(REAL)
        twin_ev = evaluation([pair("A", "B", 1500, 700, 0.15, "rotation-only"),
                              pair("A", "C", 300, 200, 0.5),
                              pair("B", "C", 0, success=False, reason="screened out (no shared view)")],
                             [("A", True, True), ("B", True, True), ("C", False, False)])
        self.twin = ts.summarise_calibration(twin_ev)
        self.comparison = ts.compare_with_real(self.real, self.twin)

    def test_targets(self):
        c = self.comparison
        self.assertAlmostEqual(c["pairs"]["A-B"]["matches"]["ratio"], 1.5)
        self.assertFalse(c["pairs"]["A-C"]["matches"]["within"])  # 300 of 800
        self.assertTrue(c["pairs"]["B-C"]["matches"]["within"])  # screened out in both
        self.assertFalse(c["targets"]["matches_within_every_pair"])
        self.assertTrue(c["targets"]["inlier_ratio_within_every_pair"])  # 0.47/0.4, 0.67/0.375, none/none
        self.assertAlmostEqual(c["median_pair_rotation_error_deg"]["ratio"], 0.325 / 1.55)
        self.assertFalse(c["targets"]["median_pair_rotation_error_within"])
        self.assertFalse(c["targets"]["same_cameras_placed"])  # B placed in the twin only
        line = ts.targets_line("twin", c)
        self.assertIn("matches within 2x in every pair: no (A-C)", line)
        self.assertIn("inlier ratios within 2x in every pair: yes", line)

    def test_a_pair_the_twin_lacks_misses_the_targets(self):
        twin = dict(self.twin, pairs={k: v for k, v in self.twin["pairs"].items() if k != "A-B"})
        c = ts.compare_with_real(self.real, twin)
        self.assertFalse(c["pairs"]["A-B"]["matches"]["within"])
        self.assertFalse(c["targets"]["matches_within_every_pair"])

    def test_table_has_every_pair_and_a_ratio_column_per_twin(self):
        rows = ts.table_rows([("real", self.real, None), ("twin x", self.twin, self.comparison),
                              ("twin y", self.real, ts.compare_with_real(self.real, self.real))])
        self.assertEqual(rows[0], ["", "real", "twin x", "twin/real", "twin y", "twin/real"])
        self.assertTrue(all(len(r) == 6 for r in rows))
        labels = [r[0] for r in rows]
        for key in ("A-B", "A-C", "B-C"):
            for q in ("fit", "matches", "inliers", "inlier ratio", "rotation error"):
                self.assertIn(f"{key} {q}", labels)
        by_label = {r[0]: r for r in rows}
        self.assertEqual(by_label["A-C matches"][1:], ["800", "300", "0.38x off", "800", "1.00x ok"])
        self.assertEqual(by_label["cameras placed (full pose)"][3], "differ")
        self.assertEqual(by_label["B-C inlier ratio"][3], "same")
        self.assertEqual(by_label["median pair rotation error"][1], "1.550° (2 solved)")
        md = ts.markdown_table(rows).splitlines()
        self.assertEqual(md[1], "|---|---|---|---|---|---|")
        self.assertEqual(len(md), len(rows) + 1)


class PathTest(unittest.TestCase):
    def test_step_interval_and_turn_from_poses(self):
        # rig_from_world with the identity rotation: the centre is minus the translation.
        frames = {"frames": [{"rig_from_world": {"rotation_wxyz": [1, 0, 0, 0], "translation": [-1.5 * i, 0, 0]},
                              "timestamp_s": 0.1 * i} for i in range(3)]}
        n, step, interval, turn = ts.frames_from_poses(frames)
        self.assertEqual(n, 3)
        self.assertAlmostEqual(step, 1.5)
        self.assertAlmostEqual(interval, 0.1)
        self.assertAlmostEqual(turn, 0.0)

    def test_frames_without_poses(self):
        self.assertIsNone(ts.frames_from_poses({"frames": [{"name": "0000", "timestamp_s": 0.0}]}))
        self.assertIsNone(ts.frames_from_poses({"frames": []}))


if __name__ == "__main__":
    unittest.main()
