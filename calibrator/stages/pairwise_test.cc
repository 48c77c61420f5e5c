#include "calibrator/stages/pairwise.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include <gtest/gtest.h>

#include "calibrator/calibrate_rig.h"
#include "evaluation/pose_errors.h"
#include "labels/cityscapes.h"
#include "testing/rendered_yard.h"

namespace rigsim {
namespace {

// The yard's features (testing/rendered_yard.h) of every view, camera-major, with each keypoint's
// class; `masked`: detected on the default reliable classes only, as the mask modes do.
std::vector<FeatureSet> YardFeatures(bool masked) {
  const RenderedYard& yard = TwoCameraYard();
  const LabelIdSet reliable = ReliableClasses().Ids();
  std::vector<FeatureSet> out;
  for (size_t c = 0; c < yard.rgb.size(); ++c) {
    for (size_t f = 0; f < yard.rgb[c].size(); ++f) {
      out.push_back(DetectFeatures(yard.rgb[c][f], &yard.labels[c][f], FeatureOptions{}, masked ? &reliable : nullptr));
    }
  }
  return out;
}

const std::vector<FeatureSet>& Unmasked() {
  static const std::vector<FeatureSet> features = YardFeatures(false);
  return features;
}

const std::vector<FeatureSet>& Masked() {
  static const std::vector<FeatureSet> features = YardFeatures(true);
  return features;
}

RigViews YardViews(const std::vector<FeatureSet>& features) {
  const RenderedYard& yard = TwoCameraYard();
  RigViews views;
  for (const RigCamera& rc : yard.rig.cameras) {
    views.camera_names.push_back(rc.name);
    views.cameras.push_back(rc.camera);
  }
  views.num_frames = static_cast<int>(yard.rig_from_world.size());
  views.features = features;
  return views;
}

Rigid3d TrueCam1FromCam0() {
  const Rig& rig = TwoCameraYard().rig;
  return *rig.cameras[1].cam_from_rig * rig.cameras[0].cam_from_rig->Inverse();
}

PairwiseOptions Gated(bool gated) {
  PairwiseOptions o;
  o.matching.gate_by_class = gated;
  return o;
}

// The four semantic modes (features with or without the mask, matching with or without gating)
// on the same views: each finds the pair's pose; gating compares fewer descriptors, the mask
// leaves fewer keypoints.
TEST(MatchRigPairs, EveryModeRecoversThePose) {
  const Rigid3d truth = TrueCam1FromCam0();
  std::vector<CalibrationReport> reports;
  for (const std::vector<FeatureSet>* features : {&Unmasked(), &Masked()}) {
    for (bool gated : {false, true}) {
      reports.push_back(MatchRigPairs(YardViews(*features), Gated(gated)).report);
      const CalibrationReport& rep = reports.back();
      ASSERT_EQ(rep.pairs.size(), 1u);
      const PairResult& pr = rep.pairs[0];
      EXPECT_EQ(pr.cam_a, "cam0");
      EXPECT_EQ(pr.cam_b, "cam1");
      EXPECT_EQ(pr.frames, 2);
      ASSERT_TRUE(pr.two_view.success) << pr.two_view.failure_reason;
      EXPECT_FALSE(pr.two_view.rotation_only);
      EXPECT_GT(pr.two_view.num_matches, 50);
      EXPECT_LT(RotationErrorDeg(pr.two_view.cam_b_from_cam_a, truth), 0.3);
      EXPECT_LT(TranslationDirectionErrorDeg(pr.two_view.cam_b_from_cam_a, truth).value(), 5.0);
    }
  }
  EXPECT_LT(reports[1].pairs[0].distance_evaluations, reports[0].pairs[0].distance_evaluations);  // gated
  EXPECT_LT(reports[2].mean_keypoints_per_image, reports[0].mean_keypoints_per_image);            // masked
}

TEST(MatchRigPairs, ThreadCountDoesNotChangeResults) {
  PairwiseOptions one = Gated(true), two = Gated(true);
  one.num_threads = 1;
  two.num_threads = 2;
  const CalibrationReport a = MatchRigPairs(YardViews(Unmasked()), one).report;
  const CalibrationReport b = MatchRigPairs(YardViews(Unmasked()), two).report;
  EXPECT_EQ(a.pairs[0].two_view.num_matches, b.pairs[0].two_view.num_matches);
  EXPECT_EQ(a.pairs[0].two_view.num_inliers, b.pairs[0].two_view.num_inliers);
  EXPECT_EQ(a.pairs[0].two_view.cam_b_from_cam_a.rotation.coeffs(), b.pairs[0].two_view.cam_b_from_cam_a.rotation.coeffs());
}

TEST(MatchRigPairs, MatchDataHoldsTheMatchesAndInliersPerFrame) {
  for (const std::vector<FeatureSet>* features : {&Unmasked(), &Masked()}) {
    PairwiseOptions options;
    options.keep_match_details = true;
    const PairwiseResult r = MatchRigPairs(YardViews(*features), options);
    const PairwiseMatchData& data = r.matches;
    ASSERT_EQ(data.keypoints.size(), 2u);     // frames
    ASSERT_EQ(data.keypoints[0].size(), 2u);  // cameras
    EXPECT_EQ(data.keypoints[0][0].size(), (*features)[0].keypoints.size());
    ASSERT_EQ(data.inliers.size(), 1u);  // pairs
    size_t matches = 0, inliers = 0, flagged = 0;
    for (int f = 0; f < 2; ++f) {
      for (const auto& [a, b] : data.inliers[0][f]) {
        ASSERT_LT(a, static_cast<int>(data.keypoints[f][0].size()));
        ASSERT_LT(b, static_cast<int>(data.keypoints[f][1].size()));
      }
      ASSERT_EQ(data.match_inlier[0][f].size(), data.matches[0][f].size());
      matches += data.matches[0][f].size();
      inliers += data.inliers[0][f].size();
      for (char in : data.match_inlier[0][f]) flagged += in;
    }
    EXPECT_EQ(static_cast<int>(matches), r.report.pairs[0].two_view.num_matches);
    EXPECT_EQ(static_cast<int>(inliers), r.report.pairs[0].two_view.num_inliers);
    EXPECT_EQ(flagged, inliers);
    ASSERT_EQ(data.keypoint_classes.size(), data.keypoints.size());
    EXPECT_EQ(data.keypoint_classes[0][0].size(), data.keypoints[0][0].size());
    // Each camera between the two frames.
    ASSERT_EQ(data.temporal.size(), 2u);
    EXPECT_TRUE(data.temporal[0].two_view.success) << data.temporal[0].two_view.failure_reason;
  }
}

// Screening only decides which pairs get the full matching: a pair that passes is matched and
// solved exactly as without screening; one that fails is reported with the reason.
TEST(MatchRigPairs, ScreeningKeepsAnOverlappingPairUnchangedAndReportsOneItDrops) {
  PairwiseOptions screened, full, starved;
  full.screen_features = 0;
  starved.screen_features = 12;  // too few keypoints for any two-view fit
  const CalibrationReport a = MatchRigPairs(YardViews(Unmasked()), screened).report;
  const CalibrationReport b = MatchRigPairs(YardViews(Unmasked()), full).report;
  ASSERT_TRUE(a.pairs[0].two_view.success) << a.pairs[0].two_view.failure_reason;
  EXPECT_EQ(a.pairs[0].two_view.num_matches, b.pairs[0].two_view.num_matches);
  EXPECT_EQ(a.pairs[0].two_view.num_inliers, b.pairs[0].two_view.num_inliers);
  EXPECT_EQ(a.pairs[0].two_view.cam_b_from_cam_a.rotation.coeffs(), b.pairs[0].two_view.cam_b_from_cam_a.rotation.coeffs());
  EXPECT_GT(a.screen_time_s, 0.0);
  EXPECT_EQ(b.screen_time_s, 0.0);

  const CalibrationReport c = MatchRigPairs(YardViews(Unmasked()), starved).report;
  EXPECT_FALSE(c.pairs[0].two_view.success);
  EXPECT_EQ(c.pairs[0].two_view.num_matches, 0);
  EXPECT_EQ(c.pairs[0].distance_evaluations, 0);
  EXPECT_EQ(c.pairs[0].Outcome(), PairOutcome::kScreenedOut) << c.pairs[0].two_view.failure_reason;
}

TEST(MatchRigPairs, ViewsThatDoNotFitAreRefused) {
  RigViews views = YardViews(Unmasked());
  views.num_frames = 3;
  EXPECT_THROW(MatchRigPairs(views, {}), std::invalid_argument);
}

// What a report shows (RigCalibrationOptions::keep_details): the same result, plus every match
// with its inlier flag, the keypoints' classes, the points and residuals of the bundle adjustment.
TEST(CalibrateRig, KeptDetailsChangeNothing) {
  RigCalibrationOptions plain;
  RigCalibrationOptions keep = plain;
  keep.keep_details = true;
  const RigCalibrationResult a = CalibrateRig(YardViews(Unmasked()), plain);
  const RigCalibrationResult b = CalibrateRig(YardViews(Unmasked()), keep);
  EXPECT_FALSE(a.details);
  ASSERT_TRUE(b.details);
  ASSERT_TRUE(a.rig.cameras[1].cam_from_rig && b.rig.cameras[1].cam_from_rig);
  EXPECT_EQ(a.rig.cameras[1].cam_from_rig->translation, b.rig.cameras[1].cam_from_rig->translation);
  EXPECT_EQ(a.pairwise.pairs[0].two_view.num_inliers, b.pairwise.pairs[0].two_view.num_inliers);
  const PairwiseMatchData& md = b.details->matches;
  ASSERT_EQ(md.matches.size(), 1u);
  int matches = 0, inliers = 0;
  for (size_t f = 0; f < md.matches[0].size(); ++f) {
    ASSERT_EQ(md.match_inlier[0][f].size(), md.matches[0][f].size());
    matches += int(md.matches[0][f].size());
    for (char in : md.match_inlier[0][f]) inliers += in;
  }
  EXPECT_EQ(matches, b.pairwise.pairs[0].two_view.num_matches);
  EXPECT_EQ(inliers, b.pairwise.pairs[0].two_view.num_inliers);
  ASSERT_EQ(md.keypoint_classes.size(), md.keypoints.size());
  EXPECT_EQ(int(b.details->points.size()), b.num_points);
  EXPECT_EQ(int(b.details->final_residuals_px.size()), b.num_observations);
  EXPECT_GE(b.details->initial_residuals_px.size(), b.details->final_residuals_px.size());
  ASSERT_EQ(b.details->rotation_averaging.size(), 2u);
  EXPECT_TRUE(b.details->rotation_averaging[1].has_value());
  // The points are in the result's world (camera 0 at frame 0) and scale: in front of camera 0
  // and reprojecting near their keypoints, which the residuals say.
  int in_front = 0;
  for (const Eigen::Vector3d& x : b.details->points) in_front += x.z() > 0;
  EXPECT_GT(in_front, 0.9 * b.details->points.size());
  std::vector<double> r = b.details->final_residuals_px;
  std::sort(r.begin(), r.end());
  EXPECT_LT(r[r.size() / 2], 1.0);
}

// The whole rig calibration in memory (two cameras: one pair), metric with the known distance.
TEST(CalibrateRig, RecoversTheRigFromTheViewsAlone) {
  RigCalibrationOptions options;
  options.known_distance = KnownDistance{"cam0", "cam1", Eigen::Vector3d(0.6, 0.05, 0.1).norm()};  // the yard's baseline
  const RigCalibrationResult r = CalibrateRig(YardViews(Unmasked()), options);
  ASSERT_EQ(r.camera_status.size(), 2u);
  EXPECT_EQ(r.camera_status[1].outcome, CameraOutcome::kCalibrated) << r.camera_status[1];
  EXPECT_EQ(r.scale_kind, ScaleKind::kMetric);
  ASSERT_TRUE(r.rig.cameras[1].cam_from_rig.has_value());
  const Rigid3d truth = TrueCam1FromCam0();
  const Rigid3d& est = *r.rig.cameras[1].cam_from_rig;
  EXPECT_LT(RotationErrorDeg(est, truth), 0.3);
  EXPECT_LT(TranslationDirectionErrorDeg(est, truth).value(), 5.0);
  EXPECT_LT((est.SourceOriginInTarget() - truth.SourceOriginInTarget()).norm(), 0.06);
  EXPECT_GT(r.num_points, 30);
  EXPECT_LT(r.reprojection_rms_px, 1.0);
  EXPECT_EQ(r.pairwise.pairs.size(), 1u);
  std::printf("rot %.3f deg, dir %.3f deg, RMS %.3f px, %d points\n", RotationErrorDeg(est, truth),
              *TranslationDirectionErrorDeg(est, truth), r.reprojection_rms_px, r.num_points);
}

}  // namespace
}  // namespace rigsim
