#include "pipeline/calibration_scores.h"

#include <gtest/gtest.h>

#include "pipeline/pipeline_test_support.h"

namespace rigsim {
namespace {

// What evaluate scores: a placed camera's pose, a rotation-only camera's rotation, nothing for a
// camera not connected.
TEST(RigEstimateOf, PosesRotationsAndNothing) {
  RigCalibrationResult r;
  r.semantic_mode = "mask";
  r.scale_kind = ScaleKind::kMetric;
  const Camera cam(CameraModelId::kPinhole, 64, 48, {50, 50, 32, 24});
  const Rigid3d placed(Eigen::Quaterniond(Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitY())), Eigen::Vector3d(1, 0, 0));
  const Eigen::Quaterniond turned(Eigen::AngleAxisd(0.7, Eigen::Vector3d::UnitY()));
  r.rig.cameras = {{"a", cam, Rigid3d(), 0.0}, {"b", cam, placed, 0.0}, {"c", cam, std::nullopt, 0.0},
                   {"d", cam, std::nullopt, 0.0}};
  r.cam_from_rig_rotation = {Eigen::Quaterniond::Identity(), placed.rotation, turned, std::nullopt};
  const RigEstimate e = RigEstimateOf(r);
  EXPECT_EQ(e.method, "mask");
  EXPECT_TRUE(e.metric);
  ASSERT_EQ(e.cam_from_rig.size(), 4u);
  ASSERT_TRUE(e.cam_from_rig[1].has_value());
  EXPECT_TRUE(e.cam_from_rig[1]->translation.isApprox(placed.translation));
  EXPECT_FALSE(e.rotation_only[1].has_value());  // placed: the pose says it all
  EXPECT_FALSE(e.cam_from_rig[2].has_value());
  ASSERT_TRUE(e.rotation_only[2].has_value());
  EXPECT_TRUE(e.rotation_only[2]->isApprox(turned));
  EXPECT_FALSE(e.cam_from_rig[3].has_value());
  EXPECT_FALSE(e.rotation_only[3].has_value());
}

TEST(PoolMatchPrecision, PoolsThePairsCountsAndTheirClassesWhereKnown) {
  CalibrationScores s;
  s.pairs.resize(3);
  s.pairs[0].matches_evaluated = 100;
  s.pairs[0].matches_correct = 90;
  s.pairs[0].cross_class_matches = 10;
  s.pairs[0].cross_class_correct = 4;
  s.pairs[1].matches_evaluated = 50;
  s.pairs[1].matches_correct = 20;  // no labels: no cross-class counts
  const PooledMatchPrecision p = PoolMatchPrecision(s);
  EXPECT_EQ(p.evaluated, 150);
  EXPECT_EQ(p.correct, 110);
  EXPECT_DOUBLE_EQ(p.Precision().value(), 110.0 / 150);
  ASSERT_TRUE(p.cross_class.has_value());
  EXPECT_EQ(*p.cross_class, 10);
  EXPECT_EQ(p.cross_class_correct, 4);
  EXPECT_FALSE(PoolMatchPrecision(CalibrationScores{}).Precision().has_value());
  EXPECT_FALSE(PoolMatchPrecision(CalibrationScores{}).cross_class.has_value());
}

// A match image shows a pair's inliers in one frame; their verdicts are those of the same matches
// in the match precision.
TEST(InlierVerdicts, AreTheVerdictsOfTheInliersAmongTheMatches) {
  PairwiseMatchData md;
  md.matches = {{{{0, 0}, {1, 2}, {2, 1}, {3, 3}}}};
  md.inliers = {{{{1, 2}, {3, 3}}}};
  CalibrationScores s;
  s.match_correct = {{{1, 0, 1, 1}}};
  EXPECT_EQ(InlierVerdicts(s, md, 0, 0), (std::vector<signed char>{0, 1}));
  s.match_correct = {{{}}};  // not checked: no range images
  EXPECT_TRUE(InlierVerdicts(s, md, 0, 0).empty());
}

TEST(CameraWithinTolerance, JudgesARotationOnlyCameraOnItsRotationAndAMissingOneAsWrong) {
  EXPECT_FALSE(CameraWithinTolerance(nullptr).has_value());  // no truth
  CameraAgainstTruth t;
  EXPECT_EQ(CameraWithinTolerance(&t), false);  // no estimate
  t.rotation_error_deg = 0.5;
  EXPECT_EQ(CameraWithinTolerance(&t), true);
  t.translation_direction_error_deg = 6.0;
  EXPECT_EQ(CameraWithinTolerance(&t), false);
}

TEST(CameraWithinTolerance, JudgesACameraPlacedButForOneAxisOnItsDirectionAcrossTheAxisToo) {
  CameraAgainstTruth t;
  t.rotation_error_deg = 0.5;
  t.across_axis_direction_error_deg = 4.0;
  EXPECT_EQ(CameraWithinTolerance(&t), true);
  t.across_axis_direction_error_deg = 6.0;
  EXPECT_EQ(CameraWithinTolerance(&t), false);
}

// A camera placed but for one axis: its rotation, axis and centre across the axis, none of it a
// full pose.
TEST(RigEstimateOf, CarriesACameraPlacedButForOneAxis) {
  RigCalibrationResult r;
  const Camera cam(CameraModelId::kPinhole, 64, 48, {50, 50, 32, 24});
  const Eigen::Quaterniond turned(Eigen::AngleAxisd(0.7, Eigen::Vector3d::UnitY()));
  r.rig.cameras = {{"a", cam, Rigid3d(), 0.0}, {"b", cam, std::nullopt, 0.0}, {"c", cam, std::nullopt, 0.0}};
  r.cam_from_rig_rotation = {Eigen::Quaterniond::Identity(), turned, turned};
  r.open_axis = {std::nullopt, Eigen::Vector3d::UnitY(), std::nullopt};
  r.partial_centre = {std::nullopt, Eigen::Vector3d(0.5, 0, 1), std::nullopt};
  const RigEstimate e = RigEstimateOf(r);
  ASSERT_EQ(e.open_axis.size(), 3u);
  EXPECT_FALSE(e.cam_from_rig[1].has_value());
  ASSERT_TRUE(e.rotation_only[1].has_value());
  ASSERT_TRUE(e.open_axis[1].has_value());
  EXPECT_TRUE(e.open_axis[1]->axis.isApprox(Eigen::Vector3d::UnitY()));
  EXPECT_TRUE(e.open_axis[1]->centre_across_axis.isApprox(Eigen::Vector3d(0.5, 0, 1)));
  EXPECT_FALSE(e.open_axis[0].has_value());
  EXPECT_FALSE(e.open_axis[2].has_value());  // rotation only
}

}  // namespace
}  // namespace rigsim
