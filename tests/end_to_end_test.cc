// The whole chain on the built-in street: load the shipped scene, render a small ring rig,
// calibrate every pair with and without semantics, and compare with the rendered truth.
#include <algorithm>
#include <filesystem>
#include <string>

#include <gtest/gtest.h>

#include "dataset/dataset.h"
#include "dataset/image_io.h"
#include "geometry/json_io.h"
#include "gltf/gltf_loader.h"
#include "labels/cityscapes.h"
#include "pipeline/calibration_run.h"
#include "renderer/render_dataset.h"
#include "rigs/rig_presets.h"
#include "rigs/trajectories.h"
#include "testing/temp_dir.h"

namespace rigsim {
namespace {
namespace fs = std::filesystem;

// The demo's rig on the street, `frames` frames of the demo path at `spp` samples per pixel, in a
// folder of the running test suite.
TempDir* RenderDemoRig(int frames, int spp) {
  auto* dir = new TempDir();
  const Scene scene = LoadGltf("assets/scenes/street.glb");
  RenderJob job;
  job.scene = &scene;
  job.scene_name = "street.glb";
  job.rig = MakeRingRig(RingRigOptions{});
  job.frames = MakeDemoTrajectory(frames);
  job.options.samples_per_pixel = spp;
  job.options.seed = 1;
  RenderDataset(job, *dir, true);
  return dir;
}

// Exactly the demo's dataset (rig, motion, samples, seed), so the calibration test checks what
// the demo prints. Fewer frames or lower resolution leave the 30% overlaps too few matches for
// 0.1 deg (measured: 0.4-1.0 deg with 1 frame at 640x360).
class StreetEndToEnd : public testing::Test {
 protected:
  static void SetUpTestSuite() { dir_ = RenderDemoRig(4, 4); }
  static void TearDownTestSuite() { delete dir_; }
  static TempDir* dir_;
};
TempDir* StreetEndToEnd::dir_ = nullptr;

// The demo's first frame at 1 spp: enough for the checks of the rendered ground truth, at a
// twentieth of the demo's rendering time.
class StreetFirstFrame : public testing::Test {
 protected:
  static void SetUpTestSuite() { dir_ = RenderDemoRig(1, 1); }
  static void TearDownTestSuite() { delete dir_; }
  static TempDir* dir_;
};
TempDir* StreetFirstFrame::dir_ = nullptr;

// Neighbouring pairs have a median rotation error below 0.1 deg, and every camera of the ring is
// within 0.05 deg in rotation and 0.5 deg in translation direction, in every semantic mode.
TEST_F(StreetEndToEnd, DemoRigCalibratesAccuratelyInEverySemanticMode) {
  const std::vector<SemanticMode> modes(std::begin(kAllSemanticModes), std::end(kAllSemanticModes));
  const CalibrationRun run = CalibrateDataset(*dir_, CalibrationRunOptions{}, modes);
  ASSERT_EQ(run.results.size(), 4u);
  for (size_t m = 0; m < run.results.size(); ++m) {
    const RigCalibrationResult& result = run.results[m];
    SCOPED_TRACE(result.semantic_mode);
    const CalibrationScores* truth = run.Truth(m);
    ASSERT_NE(truth, nullptr);
    const CalibrationReport& report = result.pairwise;
    ASSERT_EQ(report.pairs.size(), 6u);
    std::vector<double> rotation;
    for (size_t p = 0; p < report.pairs.size(); ++p) {
      const PairResult& pair = report.pairs[p];
      const PairAgainstTruth& pair_truth = truth->pairs[p];
      SCOPED_TRACE(pair.cam_a + "-" + pair.cam_b);
      const bool neighbours = pair.cam_a.back() + 1 == pair.cam_b.back();
      if (!neighbours) {
        EXPECT_FALSE(pair.two_view.success) << "these cameras share nothing";
        continue;
      }
      ASSERT_TRUE(pair.two_view.success) << pair.two_view.failure_reason;
      ASSERT_TRUE(pair_truth.rotation_error_deg.has_value());
      rotation.push_back(*pair_truth.rotation_error_deg);
      // Ground-truth precision of the ratio-tested matches: about 55-70% in these overlaps.
      ASSERT_TRUE(pair_truth.match_precision.has_value());
      EXPECT_GT(*pair_truth.match_precision, 0.4);
      EXPECT_GT(pair.two_view.num_inliers, 500);
    }
    ASSERT_EQ(rotation.size(), 3u);
    std::sort(rotation.begin(), rotation.end());
    EXPECT_LT(rotation[1], 0.1);

    for (size_t c = 1; c < result.rig.cameras.size(); ++c) {
      const RigCameraStats& stats = result.camera_stats[c];
    SCOPED_TRACE(result.rig.cameras[c].name + ": stated sd " + std::to_string(stats.rotation_std_deg.value_or(-1)) +
                 " deg (rotation), " + std::to_string(stats.direction_std_deg.value_or(-1)) + " deg (direction)");
      ASSERT_TRUE(result.rig.cameras[c].cam_from_rig.has_value()) << result.camera_status[c];
      EXPECT_LT(truth->cameras[c].rotation_error_deg.value(), 0.05);
      EXPECT_LT(truth->cameras[c].translation_direction_error_deg.value(), 0.5);
    }
  }
}

TEST_F(StreetFirstFrame, LabelsLineUpWithTheImage) {
  // Sky pixels (label 23) are where the range image has no surface, and vice versa.
  const DatasetLayout layout(*dir_);
  for (const std::string cam : {"cam0", "cam1", "cam2"}) {
    const ImageU8 labels = ReadImageU8(layout.Label(cam, "000000"));
    const ImageF range = ReadImageF(layout.Depth(cam, "000000"));
    const ImageU8 rgb = ReadImageU8(layout.Image(cam, "000000"));
    ASSERT_TRUE(labels.SameSize(rgb.width, rgb.height));
    int sky = 0;
    double sky_blue_minus_red = 0;
    for (int y = 0; y < labels.height; ++y) {
      for (int x = 0; x < labels.width; ++x) {
        const bool is_sky = labels.at(x, y) == kSkyId;
        EXPECT_EQ(is_sky, range.at(x, y) == 0.0f) << cam << " at " << x << "," << y;
        if (is_sky) {
          ++sky;
          sky_blue_minus_red += double(rgb.at(x, y, 2)) - rgb.at(x, y, 0);
        }
      }
    }
    // The street has sky above it, and the sky is blue in the image where the labels say so.
    ASSERT_GT(sky, 100) << cam;
    EXPECT_GT(sky_blue_minus_red / sky, 20.0) << cam;
  }
}

TEST_F(StreetFirstFrame, OverlapOfNeighboursIsInTheDesignedRange) {
  const json_io::Json overlap = json_io::ReadFile(DatasetLayout(*dir_).OverlapJson());
  for (const auto& p : overlap["pairs"]) {
    if (p["a"] == "cam0" && p["b"] == "cam1") {
      EXPECT_GT(p["overlap_a_in_b"].get<double>(), 0.15);
      EXPECT_LT(p["overlap_a_in_b"].get<double>(), 0.5);
    }
    if (p["a"] == "cam0" && p["b"] == "cam2") {
      EXPECT_LT(p["overlap_a_in_b"].get<double>(), 0.05);
    }
  }
}

// A vehicle-like surround rig whose side cameras are 190-degree fisheyes (neighbours
// share 12-14% of their views) calibrates to within 0.1 deg for every camera, and places each
// within a degree and within three of the standard deviations it states.
TEST(SurroundEndToEnd, RigWithTwoFisheyesCalibratesWithinATenthOfADegree) {
  const TempDir dir;
  const Scene scene = LoadGltf("assets/scenes/street.glb");
  RenderJob job;
  job.scene = &scene;
  job.scene_name = "street.glb";
  job.rig = MakeSurroundRig(SurroundRigOptions{});
  job.frames = MakeDemoTrajectory(4);
  job.options.samples_per_pixel = 4;
  job.options.seed = 1;
  RenderDataset(job, dir, true);
  const CalibrationRun run = CalibrateDataset(dir.path(), CalibrationRunOptions{}, {SemanticMode::kNone});
  const RigCalibrationResult& result = run.results.at(0);
  ASSERT_NE(run.Truth(0), nullptr);
  const std::vector<CameraAgainstTruth>& truth = run.Truth(0)->cameras;
  int fisheyes = 0;
  for (size_t c = 1; c < result.rig.cameras.size(); ++c) {
    const RigCameraStats& stats = result.camera_stats[c];
    SCOPED_TRACE(result.rig.cameras[c].name + ": stated sd " + std::to_string(stats.rotation_std_deg.value_or(-1)) +
                 " deg (rotation), " + std::to_string(stats.direction_std_deg.value_or(-1)) + " deg (direction)");
    fisheyes += result.rig.cameras[c].camera.model() == CameraModelId::kOpenCVFisheye;
    ASSERT_TRUE(result.rig.cameras[c].cam_from_rig.has_value()) << result.camera_status[c];
    EXPECT_LT(truth[c].rotation_error_deg.value(), 0.1);  // measured 0.028-0.057
    // Measured 0.60 deg at a stated 0.24 for the right fisheye, <= 0.18 deg for the others.
    EXPECT_LT(truth[c].translation_direction_error_deg.value(), 1.0);
    ASSERT_TRUE(stats.direction_std_deg.has_value());
    EXPECT_LT(truth[c].translation_direction_error_deg.value(), 3.0 * *stats.direction_std_deg);
  }
  EXPECT_EQ(fisheyes, 2);
}

}  // namespace
}  // namespace rigsim
