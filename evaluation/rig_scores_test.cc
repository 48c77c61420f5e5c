#include "evaluation/rig_scores.h"

#include <cmath>

#include <gtest/gtest.h>

namespace rigsim {
namespace {

// Three cameras: cam0 at the rig origin, cam1 1 m to the right turned 30 deg, cam2 1 m ahead.
Rig Truth() {
  Rig rig;
  const Camera cam(CameraModelId::kPinhole, 64, 48, {50, 50, 31.5, 23.5});
  const auto yaw = [](double deg) { return Eigen::Quaterniond(Eigen::AngleAxisd(DegToRad(deg), Eigen::Vector3d::UnitY())); };
  // cam_from_rig = (R, -R C) for a camera at centre C.
  const auto pose = [&](double deg, const Eigen::Vector3d& centre) {
    const Eigen::Quaterniond r = yaw(deg).inverse();
    return Rigid3d(r, -(r * centre));
  };
  rig.cameras.push_back({"cam0", cam, pose(0, {0, 0, 0})});
  rig.cameras.push_back({"cam1", cam, pose(30, {1, 0, 0})});
  rig.cameras.push_back({"cam2", cam, pose(0, {0, 0, 1})});
  return rig;
}

RigEstimate EstimateOf(const Rig& rig, const std::string& method = "test") {
  RigEstimate e;
  e.method = method;
  for (const RigCamera& c : rig.cameras) {
    e.cam_from_rig.push_back(c.cam_from_rig);
    e.rotation_only.push_back(std::nullopt);
    e.open_axis.push_back(std::nullopt);
  }
  return e;
}

// The truth but camera `cam` placed but for `axis` (unit): its rotation, and its centre across the
// axis at a third of the true length (an estimate is up to scale), turned `turn_deg` about the axis.
RigEstimate OpenAxisEstimate(const Rig& truth, size_t cam, const Eigen::Vector3d& axis, double turn_deg) {
  RigEstimate e = EstimateOf(truth);
  const Eigen::Vector3d centre = truth.cameras[cam].cam_from_rig->SourceOriginInTarget();
  e.rotation_only[cam] = e.cam_from_rig[cam]->rotation;
  e.cam_from_rig[cam].reset();
  const Eigen::Vector3d across = centre - axis * axis.dot(centre);
  e.open_axis[cam] = OpenAxisCentre{axis, Eigen::AngleAxisd(DegToRad(turn_deg), axis) * across / 3.0};
  return e;
}

// `rig` with camera `cam` moved by `shift` (its rotation kept).
Rig Moved(Rig rig, size_t cam, const Eigen::Vector3d& shift) {
  Rigid3d& p = *rig.cameras[cam].cam_from_rig;
  p.translation -= p.rotation * shift;
  return rig;
}

TEST(RigScores, TheTruthInAnyRigFrameAndScoreIsPerfect) {
  const Rig truth = Truth();
  // The same rig in another rig frame (rig moved and turned) and at half the scale.
  RigEstimate e = EstimateOf(truth);
  const Rigid3d rig_from_other(Eigen::Quaterniond(Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized())),
                               Eigen::Vector3d(3, -2, 5));
  for (auto& p : e.cam_from_rig) {
    p = *p * rig_from_other;
    p->translation *= 0.5;
  }
  const RigScores s = ScoreRig(truth, e);
  EXPECT_NEAR(s.scale, 2.0, 1e-9);
  EXPECT_EQ(s.cameras_posed, 3);
  EXPECT_NEAR(*s.max_rotation_error_deg, 0.0, 1e-6);
  EXPECT_NEAR(*s.max_direction_error_deg, 0.0, 1e-6);
  EXPECT_NEAR(*s.max_position_error_m, 0.0, 1e-9);
  EXPECT_TRUE(s.success_1deg);
  for (int t = 0; t < 4; ++t) {
    EXPECT_NEAR(s.auc_cameras[t], 1.0, 1e-6);
    EXPECT_NEAR(s.auc_pairs[t], 1.0, 1e-6);
  }
  EXPECT_EQ(s.pairs.size(), 3u);
}

TEST(RigScores, KnownErrorsAreMeasured) {
  const Rig truth = Truth();
  RigEstimate e = EstimateOf(truth);
  // cam1 turned 3 deg more about its vertical axis (its centre stays): rotation error 3 deg only.
  const Rigid3d& t1 = *truth.cameras[1].cam_from_rig;
  const Eigen::Vector3d c1 = t1.Inverse().translation;
  const Eigen::Quaterniond r1 = Eigen::Quaterniond(Eigen::AngleAxisd(DegToRad(3), Eigen::Vector3d::UnitY())) * t1.rotation;
  e.cam_from_rig[1] = Rigid3d(r1, -(r1 * c1));
  // cam2's centre moved sideways to (0.1, 0, 1): direction off by atan(0.1) = 5.71 deg.
  const Eigen::Quaterniond r2 = truth.cameras[2].cam_from_rig->rotation;
  e.cam_from_rig[2] = Rigid3d(r2, -(r2 * Eigen::Vector3d(0.1, 0, 1)));
  e.metric = true;
  const RigScores s = ScoreRig(truth, e);
  EXPECT_NEAR(*s.cameras[1].rotation_error_deg, 3.0, 1e-9);
  EXPECT_NEAR(*s.cameras[1].direction_error_deg, 0.0, 1e-9);
  EXPECT_NEAR(s.cameras[1].pose_error_deg, 3.0, 1e-9);
  EXPECT_NEAR(*s.cameras[2].direction_error_deg, RadToDeg(std::atan(0.1)), 1e-9);
  EXPECT_NEAR(*s.cameras[2].position_error_m, 0.1, 1e-12);  // metric: no scale fitted
  EXPECT_NEAR(s.scale, 1.0, 0.0);
  EXPECT_EQ(s.confidently_wrong, 1);  // cam2 is placed 5.7 deg off
  EXPECT_FALSE(s.success_2deg);
  // AUC over the cameras (3 and 5.71 deg) at 5 deg: (0,0)->(3,0.5) then flat to 5: (0.75 + 1) / 5.
  EXPECT_NEAR(s.auc_cameras[2], (0.5 * 0.5 * 3 + 0.5 * 2) / 5, 1e-9);
  // Pair cam0-cam1: rotation error 3 deg.
  EXPECT_EQ(s.pairs[0].cam_b, "cam1");
  EXPECT_NEAR(*s.pairs[0].rotation_error_deg, 3.0, 1e-9);
}

TEST(RigScores, MissingAndRotationOnlyCamerasAreFailuresNotZeros) {
  const Rig truth = Truth();
  RigEstimate e = EstimateOf(truth);
  e.rotation_only[1] = e.cam_from_rig[1]->rotation;
  e.cam_from_rig[1].reset();
  e.cam_from_rig[2].reset();
  const RigScores s = ScoreRig(truth, e);
  EXPECT_EQ(s.cameras_posed, 1);
  EXPECT_EQ(s.cameras_rotation_only, 1);
  EXPECT_TRUE(s.cameras[1].has_rotation);
  EXPECT_NEAR(*s.cameras[1].rotation_error_deg, 0.0, 1e-6);
  EXPECT_TRUE(std::isinf(s.cameras[1].pose_error_deg));
  EXPECT_FALSE(s.max_direction_error_deg.has_value());  // a worst error over nothing is unknown, not 0
  EXPECT_FALSE(s.max_position_error_m.has_value());
  EXPECT_EQ(s.auc_cameras[3], 0.0);
  EXPECT_FALSE(s.success_2deg);
  const nlohmann::json j = RigScoresToJson(s);
  EXPECT_TRUE(j["summary"]["max_translation_direction_error_deg"].is_null());
  EXPECT_TRUE(j["cameras"][2]["pose_error_deg"].is_null());
  // Without the reference camera nothing is in the gauge.
  RigEstimate no_ref = EstimateOf(truth);
  no_ref.cam_from_rig[0].reset();
  const RigScores r = ScoreRig(truth, no_ref);
  EXPECT_EQ(r.cameras_posed, 0);
  EXPECT_FALSE(r.success_1deg);
  EXPECT_FALSE(r.notes.empty());
}

TEST(RigScores, ACameraPlacedButForOneAxisIsScoredOnItsDirectionAcrossTheAxis) {
  const Rig truth = Truth();
  const Eigen::Vector3d up = Eigen::Vector3d::UnitY();
  const RigEstimate e = OpenAxisEstimate(truth, 1, up, 3.0);
  const RigScores s = ScoreRig(truth, e);
  EXPECT_EQ(s.cameras_posed, 2);
  EXPECT_EQ(s.cameras_open_axis, 1);
  EXPECT_EQ(s.cameras_rotation_only, 0);  // counted apart
  const CameraScore& cam1 = s.cameras[1];
  EXPECT_TRUE(cam1.open_axis);
  EXPECT_NEAR(*cam1.rotation_error_deg, 0.0, 1e-6);
  EXPECT_FALSE(cam1.direction_error_deg.has_value());
  ASSERT_TRUE(cam1.across_axis_direction_error_deg.has_value());
  EXPECT_NEAR(*cam1.across_axis_direction_error_deg, 3.0, 1e-9);
  EXPECT_NEAR(*s.max_across_axis_direction_error_deg, 3.0, 1e-9);
  EXPECT_TRUE(std::isinf(cam1.pose_error_deg));  // no full pose: never a success
  EXPECT_FALSE(s.success_2deg);
  EXPECT_EQ(s.confidently_wrong, 0);
  // The same by the calibration's own measure.
  const std::vector<CameraErrors> errors = CalibrationCameraErrors(truth, e);
  EXPECT_NEAR(errors[1].across_axis_direction_error_deg.value(), 3.0, 1e-9);
  EXPECT_FALSE(errors[1].direction_error_deg.has_value());
  EXPECT_NEAR(errors[1].rotation_error_deg.value(), 0.0, 1e-6);
  // The true centre's component along the axis is what the estimate leaves open: it does not count.
  const Rig higher = Moved(truth, 1, 0.8 * up);
  EXPECT_NEAR(ScoreRig(higher, e).cameras[1].across_axis_direction_error_deg.value(), 3.0, 1e-9);
  EXPECT_NEAR(CalibrationCameraErrors(higher, e)[1].across_axis_direction_error_deg.value(), 3.0, 1e-9);
  const nlohmann::json j = RigScoresToJson(s);
  EXPECT_EQ(j["summary"]["cameras_open_axis"], 1);
  EXPECT_NEAR(j["summary"]["max_across_axis_direction_error_deg"].get<double>(), 3.0, 1e-9);
  EXPECT_EQ(j["cameras"][1]["open_along_axis"], true);
  EXPECT_NEAR(j["cameras"][1]["across_axis_direction_error_deg"].get<double>(), 3.0, 1e-9);
  EXPECT_TRUE(j["cameras"][2]["across_axis_direction_error_deg"].is_null());
}

// ScoreRig takes the axis and the centre across it into the estimate's camera 0 frame, as the poses.
TEST(RigScores, ACameraPlacedButForOneAxisScoresTheSameInAnyRigFrame) {
  const Rig truth = Truth();
  RigEstimate e = OpenAxisEstimate(truth, 1, Eigen::Vector3d::UnitY(), 3.0);
  const Rigid3d rig_from_other(Eigen::Quaterniond(Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized())),
                               Eigen::Vector3d(3, -2, 5));
  const Rigid3d other_from_rig = rig_from_other.Inverse();
  for (auto& p : e.cam_from_rig) {
    if (!p) continue;
    p = *p * rig_from_other;
    p->translation *= 0.5;
  }
  e.rotation_only[1] = *e.rotation_only[1] * rig_from_other.rotation;
  OpenAxisCentre& open = *e.open_axis[1];
  open.axis = other_from_rig.rotation * open.axis;
  open.centre_across_axis = 0.5 * (other_from_rig * open.centre_across_axis);  // any point on the line
  const RigScores s = ScoreRig(truth, e);
  EXPECT_NEAR(*s.cameras[1].rotation_error_deg, 0.0, 1e-6);
  EXPECT_NEAR(s.cameras[1].across_axis_direction_error_deg.value(), 3.0, 1e-9);
}

TEST(RigScores, ACameraPlacedButForOneAxisMoreThanFiveDegreesOffIsConfidentlyWrong) {
  const Rig truth = Truth();
  const Eigen::Vector3d up = Eigen::Vector3d::UnitY();
  EXPECT_EQ(ScoreRig(truth, OpenAxisEstimate(truth, 1, up, 4.0)).confidently_wrong, 0);
  EXPECT_EQ(ScoreRig(truth, OpenAxisEstimate(truth, 1, up, 6.0)).confidently_wrong, 1);
  RigEstimate turned = OpenAxisEstimate(truth, 1, up, 0.0);
  turned.rotation_only[1] = Eigen::Quaterniond(Eigen::AngleAxisd(DegToRad(6.0), up)) * *turned.rotation_only[1];
  const RigScores s = ScoreRig(truth, turned);
  EXPECT_NEAR(*s.cameras[1].rotation_error_deg, 6.0, 1e-9);
  EXPECT_EQ(s.confidently_wrong, 1);
}

TEST(RigScores, ACameraOnTheOpenAxisHasNoDirectionAcrossItToJudge) {
  // cam2 sits 1 m ahead of cam0: on an axis along z through cam0, whatever its estimate says.
  const Rig truth = Truth();
  const Eigen::Vector3d ahead = Eigen::Vector3d::UnitZ();
  RigEstimate e = OpenAxisEstimate(truth, 2, ahead, 0.0);
  e.open_axis[2]->centre_across_axis = Eigen::Vector3d(0.1, 0, 0);
  const RigScores s = ScoreRig(truth, e);
  EXPECT_EQ(s.cameras_open_axis, 1);
  EXPECT_FALSE(s.cameras[2].across_axis_direction_error_deg.has_value());
  EXPECT_FALSE(s.max_across_axis_direction_error_deg.has_value());
  EXPECT_FALSE(CalibrationCameraErrors(truth, e)[2].across_axis_direction_error_deg.has_value());
  EXPECT_EQ(s.confidently_wrong, 0);  // judged on its rotation alone
  e.rotation_only[2] = Eigen::Quaterniond(Eigen::AngleAxisd(DegToRad(6.0), ahead)) * *e.rotation_only[2];
  EXPECT_EQ(ScoreRig(truth, e).confidently_wrong, 1);
}

// A camera off by more than three stated standard deviations is overconfident; one whose error
// its stated deviation covers is not, nor one for which nothing is stated (a peer's estimate).
TEST(RigScores, ErrorsBeyondThreeStatedDeviationsAreOverconfident) {
  const Rig truth = Truth();
  const Rig off = Moved(truth, 2, Eigen::Vector3d(0.05, 0, 0));  // cam2's direction 2.9 deg off
  RigEstimate e = EstimateOf(off);
  const RigScores unstated = ScoreRig(truth, e);
  EXPECT_EQ(unstated.overconfident, 0);  // nothing stated: not judged, and so shown
  EXPECT_EQ(unstated.cameras_stating_sd, 0);
  EXPECT_FALSE(unstated.cameras[2].overconfident.has_value());
  EXPECT_TRUE(RigScoresToJson(unstated)["cameras"][2]["overconfident"].is_null());
  EXPECT_EQ(FormatRigScores({unstated}).find("rot/sd"), std::string::npos);  // no ratio columns for a peer
  e.rotation_std_deg.assign(3, 0.01);
  e.direction_std_deg.assign(3, std::nullopt);
  e.direction_std_deg[2] = 2.0;
  RigScores s = ScoreRig(truth, e);
  EXPECT_EQ(s.overconfident, 0);
  e.direction_std_deg[2] = 0.5;
  s = ScoreRig(truth, e);
  EXPECT_EQ(s.overconfident, 1);
  EXPECT_EQ(s.cameras_stating_sd, 2);
  EXPECT_EQ(s.cameras[2].overconfident, true);
  EXPECT_EQ(s.cameras[1].overconfident, false);
  EXPECT_FALSE(s.cameras[0].overconfident.has_value());  // the reference is the gauge
  EXPECT_NEAR(s.cameras[2].direction_sd_ratio.value(), *s.cameras[2].direction_error_deg / 0.5, 1e-12);
  const nlohmann::json j = RigScoresToJson(s);
  EXPECT_EQ(j["summary"]["overconfident"], 1);
  EXPECT_EQ(j["summary"]["cameras_stating_sd"], 2);
  EXPECT_EQ(j["cameras"][2]["overconfident"], true);
  EXPECT_NEAR(j["cameras"][2]["error_sd_ratio"]["direction"].get<double>(), *s.cameras[2].direction_sd_ratio, 1e-12);
  // The evaluate table has the ratios and marks the camera.
  const std::string table = FormatRigScores({s});
  EXPECT_NE(table.find("rot/sd"), std::string::npos) << table;
  EXPECT_NE(table.find("full pose, overconfident"), std::string::npos) << table;
  EXPECT_NE(table.find("overconfident: 1 of 2 camera(s) that state a standard deviation"), std::string::npos) << table;
  // A rotation-only camera is judged on its rotation.
  RigEstimate turned = EstimateOf(truth);
  turned.rotation_only[1] =
      Eigen::Quaterniond(Eigen::AngleAxisd(DegToRad(1.0), Eigen::Vector3d::UnitX())) * turned.cam_from_rig[1]->rotation;
  turned.cam_from_rig[1].reset();
  turned.rotation_std_deg.assign(3, 0.5);
  EXPECT_EQ(ScoreRig(truth, turned).overconfident, 0);
  turned.rotation_std_deg[1] = 0.2;
  EXPECT_EQ(ScoreRig(truth, turned).overconfident, 1);
}

// The truth's own accuracy (--truth-sd, a survey's) counts beside the stated deviations: a truth
// coarser than the estimate cannot call it overconfident; an exact one judges as before.
TEST(RigScores, TheTruthsOwnAccuracyCountsBesideTheStatedDeviations) {
  const Rig truth = Truth();
  RigEstimate e = EstimateOf(Moved(truth, 2, Eigen::Vector3d(0.05, 0, 0)));  // cam2's direction 2.9 deg off
  e.rotation_only[1] =
      Eigen::Quaterniond(Eigen::AngleAxisd(DegToRad(0.1), Eigen::Vector3d::UnitX())) * e.cam_from_rig[1]->rotation;
  e.cam_from_rig[1].reset();  // cam1: rotation only, 0.1 deg off
  e.rotation_std_deg = {std::nullopt, 0.01, 0.01};
  e.direction_std_deg = {std::nullopt, std::nullopt, 0.5};
  const RigScores exact = ScoreRig(truth, e);
  ASSERT_EQ(exact.cameras[1].overconfident, true);
  ASSERT_EQ(exact.cameras[2].overconfident, true);
  EXPECT_TRUE(exact.truth_accuracy.Exact());
  // Positions known to 2 cm: cam2's direction is known to sqrt(2) 2 cm over its distance from cam0.
  const double distance = (truth.cameras[2].cam_from_rig->Inverse().translation -
                           truth.cameras[0].cam_from_rig->Inverse().translation).norm();
  const double truth_sd_deg = RadToDeg(std::sqrt(2.0) * 0.02 / distance);
  const RigScores coarse = ScoreRig(truth, e, {0.05, 0.02});
  EXPECT_NEAR(*coarse.cameras[2].direction_sd_ratio,
              *coarse.cameras[2].direction_error_deg / std::hypot(0.5, truth_sd_deg), 1e-12);
  EXPECT_NEAR(*coarse.cameras[1].rotation_sd_ratio, 0.1 / std::hypot(0.01, std::sqrt(2.0) * 0.05), 1e-9);
  EXPECT_EQ(coarse.cameras[1].overconfident, false);
  EXPECT_EQ(coarse.cameras[2].overconfident, false);
  EXPECT_EQ(coarse.overconfident, 0);
  // A truth good to 1 mm and 0.005 deg still finds both.
  EXPECT_EQ(ScoreRig(truth, e, {0.005, 0.001}).overconfident, 2);
  const nlohmann::json j = RigScoresToJson(coarse);
  EXPECT_DOUBLE_EQ(j["summary"]["truth_accuracy"]["position_m"].get<double>(), 0.02);
  EXPECT_DOUBLE_EQ(j["summary"]["truth_accuracy"]["rotation_deg"].get<double>(), 0.05);
  const std::string table = FormatRigScores({coarse});
  EXPECT_NE(table.find("the truth's own, 0.05 deg and 0.02 m per camera (--truth-sd)"), std::string::npos) << table;
  EXPECT_EQ(FormatRigScores({exact}).find("--truth-sd"), std::string::npos);
  EXPECT_THROW(ScoreRig(truth, e, {-0.1, 0.0}), std::invalid_argument);
}

// A pose that holds if synchronised is judged against its stated deviations where the truth's
// camera captured with camera 0, and not where it did not (the condition was stated, and is false).
TEST(RigScores, APoseIfSynchronisedIsJudgedOnlyWhereTheTruthIsSynchronised) {
  Rig truth = Truth();
  RigEstimate e = EstimateOf(Moved(truth, 2, Eigen::Vector3d(0.05, 0, 0)));  // cam2's direction 2.9 deg off
  e.if_synchronised = {0, 0, 1};
  e.direction_std_deg = {std::nullopt, 0.5, 0.5};
  RigScores s = ScoreRig(truth, e);
  EXPECT_EQ(s.cameras[2].overconfident, true);
  EXPECT_EQ(s.overconfident, 1);
  truth.cameras[2].time_offset_s = 0.03;  // captured 30 ms after cam0
  s = ScoreRig(truth, e);
  EXPECT_FALSE(s.cameras[2].overconfident.has_value());
  EXPECT_EQ(s.overconfident, 0);
  EXPECT_EQ(s.cameras_stating_sd, 1);  // cam1 only
  e.direction_std_deg[1].reset();
  s = ScoreRig(truth, e);
  EXPECT_EQ(s.cameras_stating_sd, 0);
  // Its ratio is still shown, with no verdict.
  const std::string table = FormatRigScores({s});
  EXPECT_NE(table.find("dir/sd"), std::string::npos) << table;
  EXPECT_EQ(table.find("overconfident"), std::string::npos) << table;
}

// A pose that holds if synchronised and is over 5 deg off is confidently wrong where the truth's camera
// captured with camera 0 (the condition holds), and only wrong if synchronised where it did not.
TEST(RigScores, AWrongPoseIfSynchronisedIsConfidentlyWrongWhereTheTruthIsSynchronised) {
  Rig truth = Truth();
  RigEstimate e = EstimateOf(Moved(truth, 2, Eigen::Vector3d(0.5, 0, 0)));
  e.if_synchronised = {0, 0, 1};
  RigScores s = ScoreRig(truth, e);
  ASSERT_GT(s.cameras[2].pose_error_deg, kConfidentlyWrongDeg);
  EXPECT_EQ(s.wrong_if_synchronised, 1);
  EXPECT_EQ(s.confidently_wrong, 1);
  truth.cameras[2].time_offset_s = 0.03;  // captured 30 ms after cam0: the condition is false
  s = ScoreRig(truth, e);
  EXPECT_EQ(s.wrong_if_synchronised, 1);
  EXPECT_EQ(s.confidently_wrong, 0);
  truth.cameras[2].time_offset_s = 0.0;
  truth.cameras[2].readout_s = 0.02;  // a rolling shutter: not captured with cam0 either
  EXPECT_EQ(ScoreRig(truth, e).confidently_wrong, 0);
}

// A rotation 4 stated sd off is overconfident and 2 sd off not; an error under the floor is not,
// however small the stated deviation.
TEST(RigScores, OverconfidentNeedsFourNotTwoDeviationsAndAnErrorOverTheFloor) {
  const Rig truth = Truth();
  const auto turned_by = [&](double deg) {
    RigEstimate e = EstimateOf(truth);
    e.rotation_only[1] = Eigen::Quaterniond(Eigen::AngleAxisd(DegToRad(deg), Eigen::Vector3d::UnitZ())) *
                         e.cam_from_rig[1]->rotation;
    e.cam_from_rig[1].reset();
    e.rotation_std_deg.assign(3, std::nullopt);
    return e;
  };
  RigEstimate e = turned_by(0.4);
  e.rotation_std_deg[1] = 0.1;  // 4 sd
  RigScores s = ScoreRig(truth, e);
  EXPECT_EQ(s.cameras[1].overconfident, true);
  EXPECT_NEAR(s.cameras[1].rotation_sd_ratio.value(), 4.0, 1e-9);
  e.rotation_std_deg[1] = 0.2;  // 2 sd
  EXPECT_EQ(ScoreRig(truth, e).cameras[1].overconfident, false);
  RigEstimate tiny = turned_by(0.04);
  tiny.rotation_std_deg[1] = 0.001;  // 40 sd of an error under the 0.05 deg floor
  s = ScoreRig(truth, tiny);
  EXPECT_EQ(s.cameras[1].overconfident, false);
  EXPECT_NEAR(s.cameras[1].rotation_sd_ratio.value(), 40.0, 1e-6);
  EXPECT_EQ(s.overconfident, 0);
  EXPECT_EQ(s.cameras_stating_sd, 1);
}

}  // namespace
}  // namespace rigsim
