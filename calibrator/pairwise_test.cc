#include "calibrator/pairwise.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <random>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "calibrator/rig_calibration.h"
#include "dataset/dataset.h"
#include "dataset/image_io.h"
#include "geometry/rig.h"
#include "testing/expect_error.h"
#include "testing/temp_dir.h"

namespace rigsim {
namespace {

namespace fs = std::filesystem;

// Smooth value noise in [0, 1] on a plane: blobs of about `cell` metres.
double ValueNoise(double u, double v, double cell, uint32_t salt) {
  auto hash = [salt](int64_t i, int64_t j) {
    uint64_t h = static_cast<uint64_t>(i) * 0x9E3779B97F4A7C15ull ^ static_cast<uint64_t>(j) * 0xC2B2AE3D27D4EB4Full ^ salt;
    h ^= h >> 31;
    h *= 0xBF58476D1CE4E5B9ull;
    h ^= h >> 29;
    return static_cast<double>(h & 0xFFFF) / 65535.0;
  };
  const double x = u / cell, y = v / cell;
  const int64_t i = static_cast<int64_t>(std::floor(x)), j = static_cast<int64_t>(std::floor(y));
  double fx = x - i, fy = y - j;
  fx = fx * fx * (3 - 2 * fx);
  fy = fy * fy * (3 - 2 * fy);
  const double a = hash(i, j) + fx * (hash(i + 1, j) - hash(i, j));
  const double b = hash(i, j + 1) + fx * (hash(i + 1, j + 1) - hash(i, j + 1));
  return a + fy * (b - a);
}

// A walled yard (frame: x right, y down, z forward): floor (road) at y = 1.6, back wall
// (building) at z = 9, left wall (vegetation) at x = -4, right wall (building) at x = 5; walls end
// at y = -3, above them is sky.
struct Hit {
  double range = 0.0;
  uint8_t label = kSkyId;
  double shade = 0.75;
};

Hit Trace(const Eigen::Vector3d& o, const Eigen::Vector3d& d) {
  Hit best;
  best.range = std::numeric_limits<double>::infinity();
  auto consider = [&](double t, uint8_t label, double u, double v, uint32_t salt, bool ok) {
    if (!ok || !(t > 1e-6) || t >= best.range) return;
    best.range = t;
    best.label = label;
    best.shade = 0.15 + 0.55 * ValueNoise(u, v, 0.25, salt) + 0.3 * ValueNoise(u, v, 0.07, salt + 1);
  };
  auto at = [&](double t) { return o + t * d; };
  if (d.y() > 0) {
    const double t = (1.6 - o.y()) / d.y();
    consider(t, 7, at(t).x(), at(t).z(), 11, true);
  }
  if (d.z() > 0) {
    const double t = (9.0 - o.z()) / d.z();
    consider(t, 11, at(t).x(), at(t).y(), 22, at(t).y() > -3);
  }
  if (d.x() < 0) {
    const double t = (-4.0 - o.x()) / d.x();
    consider(t, 21, at(t).z(), at(t).y(), 33, at(t).y() > -3);
  }
  if (d.x() > 0) {
    const double t = (5.0 - o.x()) / d.x();
    consider(t, 11, at(t).z(), at(t).y(), 44, at(t).y() > -3);
  }
  if (!std::isfinite(best.range)) return Hit{};
  return best;
}

Rigid3d CamFromRig(double yaw_deg, const Eigen::Vector3d& centre_in_rig) {
  const Eigen::Matrix3d r = Eigen::AngleAxisd(DegToRad(yaw_deg), Eigen::Vector3d::UnitY()).toRotationMatrix();
  return Rigid3d(r, -r * centre_in_rig);
}

// Renders a 2-camera, 2-frame dataset with images, labels and range images.
void WriteDataset(const fs::path& dir) {
  Rig rig;
  rig.cameras.push_back({"cam0", Camera(CameraModelId::kPinhole, 320, 240, {220, 220, 159.5, 119.5}),
                         CamFromRig(0, Eigen::Vector3d::Zero()), 0.0});
  rig.cameras.push_back({"cam1", Camera(CameraModelId::kOpenCV, 320, 240, {210, 211, 161, 118, -0.08, 0.01, 0, 0}),
                         CamFromRig(20, Eigen::Vector3d(0.6, 0.05, 0.1)), 0.0});
  FramesFile frames;
  frames.scene = "pairwise_test yard";
  for (int f = 0; f < 2; ++f) {
    Frame fr;
    fr.name = "00000" + std::to_string(f);
    fr.rig_from_world = Rigid3d(Eigen::Quaterniond(Eigen::AngleAxisd(DegToRad(-6.0 * f), Eigen::Vector3d::UnitY())),
                                Eigen::Vector3d(0.3 * f, 0, -0.8 * f));
    frames.frames.push_back(fr);
  }
  fs::create_directories(dir);
  WriteRig(rig, dir / "rig.json");
  WriteFrames(frames, dir / "frames.json");
  const DatasetLayout layout(dir);
  for (const RigCamera& rc : rig.cameras) {
    for (const Frame& fr : frames.frames) {
      const Rigid3d world_from_cam = (*rc.cam_from_rig * *fr.rig_from_world).Inverse();
      const Camera& cam = rc.camera;
      ImageU8 rgb(cam.width(), cam.height(), 3), labels(cam.width(), cam.height(), 1);
      ImageF range(cam.width(), cam.height(), 1, 0.f);
      for (int y = 0; y < cam.height(); ++y) {
        for (int x = 0; x < cam.width(); ++x) {
          double shade = 0.0;
          for (int s = 0; s < 4; ++s) {  // 2x2 supersampling
            const Eigen::Vector2d px(x - 0.25 + 0.5 * (s % 2), y - 0.25 + 0.5 * (s / 2));
            const auto f = cam.CamFromImg(px);
            shade += f ? Trace(world_from_cam.translation, world_from_cam.rotation * *f).shade / 4 : 0.0;
          }
          const auto f = cam.CamFromImg(Eigen::Vector2d(x, y));
          const Hit h = Trace(world_from_cam.translation, world_from_cam.rotation * *f);
          range.at(x, y) = static_cast<float>(h.range);
          labels.at(x, y) = h.label;
          for (int c = 0; c < 3; ++c) rgb.at(x, y, c) = static_cast<uint8_t>(std::clamp(255.0 * shade, 0.0, 255.0));
        }
      }
      for (const fs::path& p : {layout.Image(rc.name, fr.name), layout.Label(rc.name, fr.name),
                                layout.Depth(rc.name, fr.name)}) {
        fs::create_directories(p.parent_path());
      }
      WriteImage(layout.Image(rc.name, fr.name), rgb);
      WriteImage(layout.Label(rc.name, fr.name), labels);
      WriteImage(layout.Depth(rc.name, fr.name), range);
    }
  }
}

class PipelineTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    scratch_ = new TempDir();
    dir_ = *scratch_ / "dataset";
    WriteDataset(dir_);
  }
  static void TearDownTestSuite() { delete scratch_; }
  static TempDir* scratch_;
  static fs::path dir_;  // the dataset
};
TempDir* PipelineTest::scratch_ = nullptr;
fs::path PipelineTest::dir_;

TEST_F(PipelineTest, AllModesRecoverThePoseAndReportTruth) {
  CalibrationOptions options;
  const std::vector<SemanticMode> modes(std::begin(kAllSemanticModes), std::end(kAllSemanticModes));
  const std::vector<CalibrationReport> reports = CalibrateDatasetPairs(dir_, options, modes);
  ASSERT_EQ(reports.size(), 4u);
  for (const CalibrationReport& rep : reports) {
    SCOPED_TRACE(rep.semantic_mode);
    ASSERT_EQ(rep.pairs.size(), 1u);
    const PairResult& pr = rep.pairs[0];
    EXPECT_EQ(pr.cam_a, "cam0");
    EXPECT_EQ(pr.cam_b, "cam1");
    EXPECT_EQ(pr.frames, 2);
    ASSERT_TRUE(pr.two_view.success) << pr.two_view.failure_reason;
    EXPECT_FALSE(pr.two_view.rotation_only);
    EXPECT_GT(pr.two_view.num_matches, 50);
    ASSERT_TRUE(pr.rotation_error_deg && pr.translation_direction_error_deg);
    EXPECT_LT(*pr.rotation_error_deg, 0.3);
    EXPECT_LT(*pr.translation_direction_error_deg, 5.0);
    ASSERT_TRUE(pr.match_precision.has_value());
    EXPECT_EQ(pr.matches_evaluated, pr.two_view.num_matches);
    EXPECT_GT(*pr.match_precision, 0.7);
    EXPECT_GT(pr.inlier_precision.value(), *pr.match_precision - 1e-9);
    EXPECT_GT(rep.detect_time_s, 0.0);
  }
  // Gating compares fewer descriptor pairs than the baseline on the same features.
  EXPECT_LT(reports[2].pairs[0].distance_evaluations, reports[0].pairs[0].distance_evaluations);
  // Masking leaves fewer keypoints (vegetation and sky are gone).
  EXPECT_LT(reports[1].mean_keypoints_per_image, reports[0].mean_keypoints_per_image);

  const nlohmann::json j = ReportToJson(reports);
  ASSERT_TRUE(j["methods"].contains("mask+gated"));
  const auto& pair = j["methods"]["none"]["pairs"][0];
  EXPECT_EQ(pair["matches"].get<int>(), reports[0].pairs[0].two_view.num_matches);
  EXPECT_TRUE(pair["rotation_error_deg"].is_number());
  EXPECT_TRUE(pair["match_precision"].is_number());
  EXPECT_TRUE(j["methods"]["none"]["summary"]["pose_auc"]["5"].is_number());
}

TEST_F(PipelineTest, ThreadCountDoesNotChangeResults) {
  CalibrationOptions one, two;
  one.num_threads = 1;
  two.num_threads = 2;
  one.semantic_mode = two.semantic_mode = SemanticMode::kGated;
  const CalibrationReport a = CalibrateDatasetPairs(dir_, one);
  const CalibrationReport b = CalibrateDatasetPairs(dir_, two);
  EXPECT_EQ(a.pairs[0].two_view.num_matches, b.pairs[0].two_view.num_matches);
  EXPECT_EQ(a.pairs[0].two_view.num_inliers, b.pairs[0].two_view.num_inliers);
  EXPECT_EQ(a.pairs[0].two_view.cam_b_from_cam_a.rotation.coeffs(), b.pairs[0].two_view.cam_b_from_cam_a.rotation.coeffs());
}

TEST_F(PipelineTest, MatchDataHoldsTheInliersPerFrame) {
  CalibrationOptions options;
  std::vector<PairwiseMatchData> data;
  const std::vector<CalibrationReport> reports =
      CalibrateDatasetPairs(dir_, options, {SemanticMode::kNone, SemanticMode::kMask}, &data);
  ASSERT_EQ(data.size(), 2u);
  for (size_t m = 0; m < 2; ++m) {
    ASSERT_EQ(data[m].keypoints.size(), 2u);     // frames
    ASSERT_EQ(data[m].keypoints[0].size(), 2u);  // cameras
    ASSERT_EQ(data[m].inliers.size(), 1u);       // pairs
    size_t inliers = 0;
    for (int f = 0; f < 2; ++f) {
      for (const auto& [a, b] : data[m].inliers[0][f]) {
        ASSERT_LT(a, static_cast<int>(data[m].keypoints[f][0].size()));
        ASSERT_LT(b, static_cast<int>(data[m].keypoints[f][1].size()));
      }
      inliers += data[m].inliers[0][f].size();
    }
    EXPECT_EQ(static_cast<int>(inliers), reports[m].pairs[0].two_view.num_inliers);
  }
  // The masked mode has its own (fewer) keypoints.
  EXPECT_LT(data[1].keypoints[0][0].size(), data[0].keypoints[0][0].size());
}

// What a report shows (RigCalibrationOptions::keep_details): the same result, plus every match
// with its flags agreeing with the report's counts, the keypoints' classes, the points and
// residuals of the bundle adjustment.
TEST_F(PipelineTest, KeptDetailsAgreeWithTheReportAndChangeNothing) {
  RigCalibrationOptions plain;
  RigCalibrationOptions keep = plain;
  keep.keep_details = true;
  const RigCalibrationResult a = CalibrateRig(dir_, plain, SemanticMode::kNone);
  const RigCalibrationResult b = CalibrateRig(dir_, keep, SemanticMode::kNone);
  EXPECT_FALSE(a.details);
  ASSERT_TRUE(b.details);
  ASSERT_TRUE(a.rig.cameras[1].cam_from_rig && b.rig.cameras[1].cam_from_rig);
  EXPECT_EQ(a.rig.cameras[1].cam_from_rig->translation, b.rig.cameras[1].cam_from_rig->translation);
  EXPECT_EQ(a.pairwise.pairs[0].two_view.num_inliers, b.pairwise.pairs[0].two_view.num_inliers);
  const PairwiseMatchData& md = b.details->matches;
  const PairResult& pr = b.pairwise.pairs[0];
  ASSERT_EQ(md.matches.size(), 1u);
  int matches = 0, inliers = 0, evaluated = 0, correct = 0;
  for (size_t f = 0; f < md.matches[0].size(); ++f) {
    ASSERT_EQ(md.match_inlier[0][f].size(), md.matches[0][f].size());
    ASSERT_EQ(md.match_correct[0][f].size(), md.matches[0][f].size());
    matches += int(md.matches[0][f].size());
    for (char in : md.match_inlier[0][f]) inliers += in;
    evaluated += int(md.match_correct[0][f].size());
    for (char ok : md.match_correct[0][f]) correct += ok;
  }
  EXPECT_EQ(matches, pr.two_view.num_matches);
  EXPECT_EQ(inliers, pr.two_view.num_inliers);
  EXPECT_EQ(evaluated, pr.matches_evaluated);
  EXPECT_EQ(correct, pr.matches_correct);
  ASSERT_EQ(md.keypoint_classes.size(), md.keypoints.size());
  EXPECT_EQ(md.keypoint_classes[0][0].size(), md.keypoints[0][0].size());
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

// The whole rig calibration on rendered images (two cameras: one pair, unit scale or metric).
TEST_F(PipelineTest, CalibrateRigOnRenderedImages) {
  RigCalibrationOptions options;
  options.known_distance = KnownDistance{"cam0", "cam1", Eigen::Vector3d(0.6, 0.05, 0.1).norm()};  // WriteDataset's baseline
  const std::vector<RigCalibrationResult> results = CalibrateRig(dir_, options, {SemanticMode::kNone, SemanticMode::kGated});
  ASSERT_EQ(results.size(), 2u);
  for (const RigCalibrationResult& r : results) {
    SCOPED_TRACE(r.semantic_mode);
    ASSERT_EQ(r.camera_status.size(), 2u);
    EXPECT_EQ(r.camera_status[1], "calibrated");
    ASSERT_TRUE(r.evaluated);
    EXPECT_LT(r.camera_stats[1].rotation_error_deg.value(), 0.3);
    EXPECT_LT(r.camera_stats[1].translation_direction_error_deg.value(), 5.0);
    EXPECT_TRUE(r.metric_scale);
    EXPECT_LT(r.camera_stats[1].position_error_m.value(), 0.06);
    EXPECT_GT(r.num_points, 30);
    EXPECT_LT(r.reprojection_rms_px, 1.0);
    EXPECT_EQ(r.pairwise.pairs.size(), 1u);
    std::printf("%s: rot %.3f deg, dir %.3f deg, position %.4f m, RMS %.3f px, %d points\n", r.semantic_mode.c_str(),
                *r.camera_stats[1].rotation_error_deg, *r.camera_stats[1].translation_direction_error_deg,
                *r.camera_stats[1].position_error_m, r.reprojection_rms_px, r.num_points);
  }
  const nlohmann::json j = RigCalibrationToJson(results);
  EXPECT_TRUE(j["methods"]["gated"]["pairwise"]["pairs"].is_array());
}

TEST_F(PipelineTest, MissingInputsAreNamed) {
  const TempDir scratch;
  const fs::path copy = scratch / "dataset";
  fs::copy(dir_, copy, fs::copy_options::recursive);
  const DatasetLayout layout(copy);
  fs::remove_all(copy / "labels");
  CalibrationOptions options;
  options.semantic_mode = SemanticMode::kMask;
  EXPECT_THAT([&] { CalibrateDatasetPairs(copy, options); },
              ThrowsWith<std::runtime_error>(layout.Label("cam0", "000000").filename().string()));
  fs::remove(*layout.FindImage("cam1", "000001"));
  options.semantic_mode = SemanticMode::kNone;
  EXPECT_THAT([&] { CalibrateDatasetPairs(copy, options); }, ThrowsWith<std::runtime_error>("cam1", "000001"));
}

}  // namespace
}  // namespace rigsim

namespace rigsim {
namespace {

// Screening only decides which pairs get the full matching: a pair that passes is matched and
// solved exactly as without screening; one that fails is reported with the reason.
TEST_F(PipelineTest, ScreeningKeepsAnOverlappingPairUnchangedAndReportsOneItDrops) {
  CalibrationOptions screened, full, starved;
  full.screen_features = 0;
  starved.screen_features = 12;  // too few keypoints for any two-view fit
  const CalibrationReport a = CalibrateDatasetPairs(dir_, screened);
  const CalibrationReport b = CalibrateDatasetPairs(dir_, full);
  ASSERT_TRUE(a.pairs[0].two_view.success) << a.pairs[0].two_view.failure_reason;
  EXPECT_EQ(a.pairs[0].two_view.num_matches, b.pairs[0].two_view.num_matches);
  EXPECT_EQ(a.pairs[0].two_view.num_inliers, b.pairs[0].two_view.num_inliers);
  EXPECT_EQ(a.pairs[0].two_view.cam_b_from_cam_a.rotation.coeffs(), b.pairs[0].two_view.cam_b_from_cam_a.rotation.coeffs());
  EXPECT_GT(a.screen_time_s, 0.0);
  EXPECT_EQ(b.screen_time_s, 0.0);

  const CalibrationReport c = CalibrateDatasetPairs(dir_, starved);
  EXPECT_FALSE(c.pairs[0].two_view.success);
  EXPECT_EQ(c.pairs[0].two_view.num_matches, 0);
  EXPECT_EQ(c.pairs[0].distance_evaluations, 0);
  EXPECT_NE(c.pairs[0].two_view.failure_reason.find("screened out"), std::string::npos) << c.pairs[0].two_view.failure_reason;
}

}  // namespace
}  // namespace rigsim

namespace rigsim {
namespace {

// What the images say (success) and the verdict against the truth (within_tolerance) are apart:
// the 2-camera ring at 15 % overlap had a pair at 6.2 deg rotation and 30.5 deg direction error
// marked success, and counted so.
TEST(ReportToJson, APairReportedSolvedButFarOffIsNotWithinTolerance) {
  auto pair = [](double rotation_error, double direction_error) {
    PairResult p;
    p.cam_a = "cam0";
    p.cam_b = "cam1";
    p.two_view.success = true;
    p.cam_b_from_cam_a_gt = Rigid3d(Eigen::Quaterniond::Identity(), Eigen::Vector3d(1, 0, 0));
    p.rotation_error_deg = rotation_error;
    p.translation_direction_error_deg = direction_error;
    return p;
  };
  CalibrationReport report;
  report.semantic_mode = "none";
  report.pairs = {pair(6.2, 30.5), pair(0.3, 1.0), pair(0.3, 12.0), pair(0.3, 1.0)};
  report.pairs[3].two_view.success = false;
  report.pairs[3].rotation_error_deg.reset();
  report.pairs[3].translation_direction_error_deg.reset();
  EXPECT_EQ(PairWithinTolerance(report.pairs[0]), false);
  EXPECT_EQ(PairWithinTolerance(report.pairs[1]), true);
  EXPECT_EQ(PairWithinTolerance(report.pairs[2]), false);  // direction beyond 5 deg
  EXPECT_EQ(PairWithinTolerance(report.pairs[3]), false);  // failed: no pose to be right
  PairResult rotation_only = pair(0.3, 40.0);
  rotation_only.two_view.rotation_only = true;  // claims no direction: judged on its rotation
  EXPECT_EQ(PairWithinTolerance(rotation_only), true);
  PairResult photos = pair(0.3, 1.0);
  photos.cam_b_from_cam_a_gt.reset();
  EXPECT_FALSE(PairWithinTolerance(photos).has_value());

  const nlohmann::json j = ReportToJson({report});
  const nlohmann::json& m = j["methods"]["none"];
  EXPECT_EQ(m["pairs"][0]["success"], true);
  EXPECT_EQ(m["pairs"][0]["within_tolerance"], false);
  EXPECT_EQ(m["pairs"][1]["within_tolerance"], true);
  EXPECT_EQ(m["summary"]["pairs_succeeded"], 3);
  EXPECT_EQ(m["summary"]["pairs_within_tolerance"], 1);
  EXPECT_EQ(m["summary"]["pairs_succeeded_outside_tolerance"], 2);
  EXPECT_EQ(m["summary"]["tolerance"]["rotation_deg"], 2.0);
}

}  // namespace
}  // namespace rigsim
