// The whole chain on the built-in street: load the shipped scene, render a small ring rig,
// calibrate every pair with and without semantics, and compare with the rendered truth.
#include <filesystem>

#include <gtest/gtest.h>

#include "calibrator/pipeline.h"
#include "dataset/dataset.h"
#include "dataset/image_io.h"
#include "geometry/json_io.h"
#include "labels/cityscapes.h"
#include "renderer/render_dataset.h"
#include "scenes/gltf_loader.h"
#include "scenes/rig_generators.h"

namespace rigsim {
namespace {
namespace fs = std::filesystem;

class StreetEndToEnd : public testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new fs::path(fs::temp_directory_path() / "rigsim_end_to_end");
    fs::remove_all(*dir_);
    const Scene scene = LoadGltf("assets/scenes/street.glb");
    RingRigOptions ring;
    ring.num_cameras = 3;
    ring.width = 640;
    ring.height = 360;
    RenderJob job;
    job.scene = &scene;
    job.scene_name = "street.glb";
    job.rig = MakeRingRig(ring);
    job.frames = MakeStraightTrajectory(Eigen::Vector3d(0, 1.6, 4), 0.0, 1, 2.0);
    job.options.samples_per_pixel = 4;
    RenderDataset(job, *dir_, true);
  }
  static void TearDownTestSuite() {
    fs::remove_all(*dir_);
    delete dir_;
  }
  static fs::path* dir_;
};
fs::path* StreetEndToEnd::dir_ = nullptr;

TEST_F(StreetEndToEnd, NeighbouringPairsCalibrateAccuratelyWithAndWithoutSemantics) {
  CalibrationOptions options;
  const auto reports = CalibrateDatasetPairs(*dir_, options, {SemanticMode::kNone, SemanticMode::kMask});
  ASSERT_EQ(reports.size(), 2u);
  for (const CalibrationReport& report : reports) {
    SCOPED_TRACE(report.semantic_mode);
    ASSERT_EQ(report.pairs.size(), 3u);
    for (const PairResult& pair : report.pairs) {
      const bool neighbours = (pair.cam_a == "cam0" && pair.cam_b == "cam1") || (pair.cam_a == "cam1" && pair.cam_b == "cam2");
      if (!neighbours) continue;
      SCOPED_TRACE(pair.cam_a + "-" + pair.cam_b);
      ASSERT_TRUE(pair.success) << pair.failure_reason;
      ASSERT_TRUE(pair.rotation_error_deg.has_value());
      EXPECT_LT(*pair.rotation_error_deg, 0.1);
      ASSERT_TRUE(pair.translation_direction_error_deg.has_value());
      EXPECT_LT(*pair.translation_direction_error_deg, 5.0);
      ASSERT_TRUE(pair.match_precision.has_value());
      EXPECT_GT(*pair.match_precision, 0.8);
      EXPECT_GT(pair.inliers, 100);
    }
  }
}

TEST_F(StreetEndToEnd, LabelsLineUpWithTheImage) {
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

TEST_F(StreetEndToEnd, OverlapOfNeighboursIsInTheDesignedRange) {
  const json_io::Json overlap = json_io::ReadFile(DatasetLayout(*dir_).OverlapJson());
  for (const auto& p : overlap["pairs"]) {
    if (p["a"] == "cam0" && p["b"] == "cam1") {
      EXPECT_GT(p["overlap_a_in_b"].get<double>(), 0.15);
      EXPECT_LT(p["overlap_a_in_b"].get<double>(), 0.5);
    }
    if (p["a"] == "cam0" && p["b"] == "cam2") EXPECT_LT(p["overlap_a_in_b"].get<double>(), 0.05);
  }
}

}  // namespace
}  // namespace rigsim
