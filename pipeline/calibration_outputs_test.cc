#include "pipeline/calibration_outputs.h"

#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include "geometry/json_io.h"
#include "pipeline/calibration_json.h"
#include "pipeline/pipeline_test_support.h"
#include "testing/temp_dir.h"

namespace rigsim {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::json;

TEST(SelectExports, LeavesOutCamerasWithoutAFullPoseAndFramesWithoutARigPose) {
  const ExportSelection s = SelectExports(ThreeCameraResult(), ThreeFrames());
  ASSERT_EQ(s.calibrated.cameras.size(), 2u);
  EXPECT_EQ(s.calibrated.cameras[1].name, "cam1");
  EXPECT_EQ(s.cameras_exported, (std::vector<std::string>{"cam0", "cam1"}));
  ASSERT_EQ(s.cameras_omitted.size(), 1u);
  EXPECT_EQ(s.cameras_omitted[0].first, "cam2");
  EXPECT_EQ(s.cameras_omitted[0].second.outcome, CameraOutcome::kRotationOnly) << s.cameras_omitted[0].second.Text();
  ASSERT_EQ(s.colmap_frames.frames.size(), 2u);
  EXPECT_EQ(s.colmap_frames.frames[1].name, "000001");
  ASSERT_TRUE(s.colmap_frames.frames[1].rig_from_world.has_value());
  EXPECT_TRUE(s.colmap_frames.frames[1].rig_from_world->translation.isApprox(Eigen::Vector3d(0, 0, -2)));
  EXPECT_EQ(s.colmap_frames_omitted, (std::vector<std::string>{"000002"}));
}

TEST(SelectExports, WithoutFramePosesOnlyFrameZeroIsTheWorld) {
  RigCalibrationResult r = ThreeCameraResult();
  r.rig_from_world.clear();  // positions not observable: no frame poses
  const ExportSelection s = SelectExports(r, ThreeFrames());
  ASSERT_EQ(s.colmap_frames.frames.size(), 1u);
  EXPECT_EQ(s.colmap_frames.frames[0].name, "000000");
  EXPECT_TRUE(s.colmap_frames.frames[0].rig_from_world->rotation.isApprox(Eigen::Quaterniond::Identity()));
  EXPECT_EQ(s.colmap_frames_omitted, (std::vector<std::string>{"000001", "000002"}));
}

class WriteCalibrationResultsTest : public ::testing::Test {
 protected:
  void SetUp() override { fs::create_directories(dir_ / "out"); }
  const TempDir dir_;
};

TEST_F(WriteCalibrationResultsTest, WritesEveryFileAndReturnsTheNotes) {
  CalibrationRun run = RunOf({ThreeCameraResult()});
  run.inputs.dataset_dir = dir_.path();  // no images: no match images, and COLMAP names the default .png
  run.labels_used = true;
  const std::vector<std::string> notes = WriteCalibrationResults(run, dir_ / "out");

  ASSERT_EQ(notes.size(), 1u);
  EXPECT_EQ(notes[0].rfind("mask: camchain.yaml, opencv.yaml and colmap/ leave out", 0), 0u) << notes[0];
  EXPECT_NE(notes[0].find("cam2"), std::string::npos) << notes[0];
  for (const char* file : {"evaluation.json", "mask/rig.json", "mask/pairs.json", "mask/camchain.yaml",
                           "mask/opencv.yaml", "mask/colmap/cameras.txt", "mask/colmap/images.txt",
                           "mask/colmap/points3D.txt", "mask/colmap/triangulate.sh", "mask/rig_topdown.svg"}) {
    EXPECT_TRUE(fs::exists(dir_ / "out" / file)) << file;
  }
  EXPECT_FALSE(fs::exists(dir_ / "out" / "mask" / "matches")) << "no inlier samples: no matches/ folder";

  const Json evaluation = json_io::ReadFile(dir_ / "out" / "evaluation.json");
  EXPECT_EQ(evaluation["label_source"]["kind"], "truth");
  EXPECT_EQ(evaluation["label_source"]["used"], true);
  const Json& outputs = evaluation["methods"]["mask"]["outputs"];
  EXPECT_EQ(outputs["dir"], "mask");
  EXPECT_EQ(outputs["cameras_exported"], Json({"cam0", "cam1"}));
  EXPECT_EQ(outputs["cameras_omitted"][0]["name"], "cam2");
  EXPECT_EQ(outputs["colmap_frames"], Json({"000000", "000001"}));
  EXPECT_EQ(outputs["colmap_frames_omitted"], Json({"000002"}));
  EXPECT_EQ(outputs["notes"].size(), 1u);

  // COLMAP: 2 cameras x 2 posed frames.
  std::ifstream images(dir_ / "out" / "mask" / "colmap" / "images.txt");
  int image_lines = 0;
  for (std::string line; std::getline(images, line);) image_lines += line.find(".png") != std::string::npos;
  EXPECT_EQ(image_lines, 4);

  const Rig written = ReadRig(dir_ / "out" / "mask" / "rig.json");
  ASSERT_EQ(written.cameras.size(), 3u);
  EXPECT_FALSE(written.cameras[2].cam_from_rig.has_value());

  // The estimate says its gauge and unit, and its rig poses are beside it.
  const fs::path estimate = dir_ / "out" / "mask" / "rig.json";
  const std::optional<EstimateGauge> gauge = EstimateGaugeFromJsonText(json_io::ReadText(estimate), estimate.string());
  ASSERT_TRUE(gauge.has_value());
  EXPECT_EQ(gauge->rig_frame, "cam0");
  EXPECT_EQ(gauge->frames, "frames.json");
  EXPECT_EQ(gauge->metric, run.results[0].scale_kind == ScaleKind::kMetric);
  const FramesFile frames = ReadFrames(dir_ / "out" / "mask" / "frames.json");
  ASSERT_EQ(frames.frames.size(), 3u);
  ASSERT_TRUE(frames.frames[1].rig_from_world.has_value());
  EXPECT_TRUE(frames.frames[1].rig_from_world->translation.isApprox(Eigen::Vector3d(0, 0, -2)));
  EXPECT_FALSE(frames.frames[2].rig_from_world.has_value()) << "no estimated pose: none written";
  const std::string camchain = json_io::ReadText(dir_ / "out" / "mask" / "camchain.yaml");
  EXPECT_EQ(MetricMarkInComments(camchain), gauge->metric) << camchain;
  EXPECT_EQ(MetricMarkInComments(json_io::ReadText(dir_ / "out" / "mask" / "colmap" / "images.txt")), gauge->metric);
}

// The synchronisation check's measured offset of a camera it found unsynchronised goes into the
// estimate's rig.json (that camera has no pose); a synchronised camera's stays 0.
TEST(EstimatedRig, HoldsTheOffsetsTheCheckMeasured) {
  RigCalibrationResult r = ThreeCameraResult();
  r.camera_stats[1].time_offset_s = 0.0004;  // within the check's noise: synchronised
  r.camera_stats[2].time_offset_s = 0.030;
  r.camera_status[2] = {CameraOutcome::kUnsynchronised, PositionOutcome::kNotObservable, "it captures 30 ms after"};
  const Rig rig = EstimatedRig(r);
  EXPECT_EQ(rig.cameras[1].time_offset_s, 0.0);
  EXPECT_EQ(rig.cameras[2].time_offset_s, 0.030);
}

TEST(CamerasWithoutPose, ListsThemCommaSeparated) {
  EXPECT_EQ(CamerasWithoutPose(ThreeCameraResult().rig), "cam2");
  Rig all = ThreeCameraResult().rig;
  all.cameras[2].cam_from_rig = Rigid3d();
  EXPECT_EQ(CamerasWithoutPose(all), "");
}

}  // namespace
}  // namespace rigsim
