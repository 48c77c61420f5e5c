#include "pipeline/calibration_outputs.h"

#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include "geometry/json_io.h"
#include "testing/temp_dir.h"

namespace rigsim {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::json;

Rigid3d Yaw(double deg, const Eigen::Vector3d& t) {
  return Rigid3d(Eigen::Quaterniond(Eigen::AngleAxisd(DegToRad(deg), Eigen::Vector3d::UnitY())), t);
}

Camera Pinhole() { return Camera(CameraModelId::kPinhole, 640, 480, {500, 500, 319.5, 239.5}); }

// A calibration result built by hand, no images: three cameras of which cam2 got a rotation only,
// three frames of which the estimate posed the first two; pairs cam0-cam1 (solved, an edge in
// use), cam0-cam2 (failed, an inactive edge) and cam1-cam2 (solved, no rig edge).
RigCalibrationResult ThreeCameraResult() {
  RigCalibrationResult r;
  r.semantic_mode = "mask";
  r.rig.cameras = {{"cam0", Pinhole(), Rigid3d(), 0.0},
                   {"cam1", Pinhole(), Yaw(60, {-0.5, 0, 0.1}), 0.0},
                   {"cam2", Pinhole(), std::nullopt, 0.0}};
  r.cam_from_rig_rotation = {Eigen::Quaterniond::Identity(), Yaw(60, Eigen::Vector3d::Zero()).rotation,
                             Yaw(120, Eigen::Vector3d::Zero()).rotation};
  r.camera_status = {"calibrated (reference: rig frame)", "calibrated",
                     "rotation only: position not observable: too little parallax"};
  r.camera_stats.assign(3, {});
  r.rig_from_world = {Rigid3d(), Yaw(5, {0, 0, -2})};
  r.scale = "unit scale: |centre of cam1| = 1";

  CalibrationReport& rep = r.pairwise;
  rep.semantic_mode = "mask";
  rep.num_cameras = 3;
  rep.num_frames = 3;
  auto pair = [](std::string a, std::string b, bool success, int matches, int inliers) {
    PairResult p;
    p.cam_a = std::move(a);
    p.cam_b = std::move(b);
    p.frames = 3;
    p.two_view.success = success;
    p.two_view.num_matches = matches;
    p.two_view.num_inliers = inliers;
    p.two_view.pair_type = PairType::kGeneral;
    if (success) p.two_view.cam_b_from_cam_a = Yaw(60, {-1, 0, 0});
    if (!success) p.two_view.failure_reason = "too few matches";
    return p;
  };
  rep.pairs = {pair("cam0", "cam1", true, 400, 300), pair("cam0", "cam2", false, 3, 0),
               pair("cam1", "cam2", true, 200, 20)};
  rep.pairs[2].two_view.pair_type = PairType::kPlanar;

  RigEdgeStats used;
  used.cam_a = "cam0";
  used.cam_b = "cam1";
  used.inliers = 300;
  used.used = true;
  used.rotation_residual_deg = 0.25;
  used.status = "used";
  RigEdgeStats failed;
  failed.cam_a = "cam0";
  failed.cam_b = "cam2";
  failed.status = "two-view failed: too few matches";
  r.edges = {used, failed};
  return r;
}

FramesFile ThreeFrames() {
  FramesFile f;
  for (const char* name : {"000000", "000001", "000002"}) f.frames.push_back({name, std::nullopt, 0.0});
  return f;
}

TEST(SelectExports, LeavesOutCamerasWithoutAFullPoseAndFramesWithoutARigPose) {
  const ExportSelection s = SelectExports(ThreeCameraResult(), ThreeFrames());
  ASSERT_EQ(s.calibrated.cameras.size(), 2u);
  EXPECT_EQ(s.calibrated.cameras[1].name, "cam1");
  EXPECT_EQ(s.cameras_exported, (std::vector<std::string>{"cam0", "cam1"}));
  ASSERT_EQ(s.cameras_omitted.size(), 1u);
  EXPECT_EQ(s.cameras_omitted[0].first, "cam2");
  EXPECT_EQ(s.cameras_omitted[0].second.rfind("rotation only", 0), 0u) << s.cameras_omitted[0].second;
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

TEST(PairsJson, JoinsEveryPairToItsRigEdge) {
  const RigCalibrationResult r = ThreeCameraResult();
  OverlapTable overlap;
  overlap[{"cam0", "cam1"}] = overlap[{"cam1", "cam0"}] = 0.3;
  const Json j = PairsJson(r, LabelSourceJson(LabelSource::Truth(), true), overlap);
  EXPECT_EQ(j["semantic_mode"], "mask");
  EXPECT_EQ(j["num_frames"], 3);
  EXPECT_EQ(j["label_source"]["kind"], "truth");
  ASSERT_EQ(j["pairs"].size(), 3u);
  const Json& solved = j["pairs"][0];
  EXPECT_EQ(solved["pair_type"], "general");
  EXPECT_DOUBLE_EQ(solved["overlap"].get<double>(), 0.3);
  EXPECT_EQ(solved["rig_edge"]["used"], true);
  EXPECT_EQ(solved["rig_edge"]["status"], "used");
  EXPECT_DOUBLE_EQ(solved["rig_edge"]["rotation_residual_deg"].get<double>(), 0.25);
  const Json& failed = j["pairs"][1];
  EXPECT_EQ(failed["pair_type"], "failed");
  EXPECT_TRUE(failed["overlap"].is_null());
  EXPECT_EQ(failed["rig_edge"]["used"], false);
  EXPECT_TRUE(failed["rig_edge"]["rotation_residual_deg"].is_null());
  const Json& planar = j["pairs"][2];
  EXPECT_EQ(planar["pair_type"], "planar");
  EXPECT_TRUE(planar["rig_edge"].is_null());
  EXPECT_EQ(RigEdgeOf(r, r.pairwise.pairs[2]), nullptr);
  EXPECT_EQ(RigEdgeOf(r, r.pairwise.pairs[0]), &r.edges[0]);
}

TEST(EvaluationJson, HasThePairwiseReportAndTheRigPerMethod) {
  RigCalibrationResult none = ThreeCameraResult();
  none.semantic_mode = none.pairwise.semantic_mode = "none";
  const Json j = EvaluationJson({none, ThreeCameraResult()});
  ASSERT_TRUE(j.contains("methods"));
  for (const char* mode : {"none", "mask"}) {
    const Json& m = j["methods"][mode];
    EXPECT_EQ(m["pairs"].size(), 3u) << mode;
    EXPECT_EQ(m["summary"]["pairs_succeeded"], 2) << mode;
    EXPECT_EQ(m["summary"]["pairs_planar"], 1) << mode;
    EXPECT_EQ(m["num_frames"], 3) << mode;
    ASSERT_TRUE(m.contains("rig")) << mode;
    EXPECT_FALSE(m["rig"].contains("pairwise")) << "the pairwise report is the method's own entry";
    EXPECT_EQ(m["rig"]["summary"]["cameras_calibrated"], 2) << mode;
    EXPECT_EQ(m["rig"]["cameras"][2]["position_known"], false) << mode;
    EXPECT_EQ(m["rig"]["edges"].size(), 2u) << mode;
  }
}

TEST(LabelSourceJson, NamesTheNoiseModel) {
  SegmentationNoiseOptions noise;
  noise.seed = 7;
  const Json j = LabelSourceJson(LabelSource::Noisy(noise), false);
  EXPECT_EQ(j["kind"], "noisy");
  EXPECT_EQ(j["used"], false);
  EXPECT_EQ(j["noise"]["seed"], 7);
  EXPECT_FALSE(j.contains("folder"));
}

class WriteCalibrationResultsTest : public ::testing::Test {
 protected:
  void SetUp() override { fs::create_directories(dir_ / "out"); }
  const TempDir dir_;
};

TEST_F(WriteCalibrationResultsTest, WritesEveryFileAndReturnsTheNotes) {
  CalibrationRun run;
  run.inputs.dataset_dir = dir_.path();  // no images: no match images, and COLMAP names the default .png
  run.inputs.rig = ThreeCameraResult().rig;
  run.inputs.frames = ThreeFrames();
  run.modes = {SemanticMode::kMask};
  run.labels_used = true;
  run.results = {ThreeCameraResult()};
  const std::vector<std::string> notes = WriteCalibrationResults(run, dir_ / "out");

  ASSERT_EQ(notes.size(), 1u);
  EXPECT_EQ(notes[0].rfind("mask: camchain.yaml, opencv.yaml and colmap/ leave out", 0), 0u) << notes[0];
  EXPECT_NE(notes[0].find("cam2"), std::string::npos) << notes[0];
  for (const char* file : {"evaluation.json", "mask/rig.json", "mask/pairs.json", "mask/camchain.yaml",
                           "mask/opencv.yaml", "mask/colmap/cameras.txt", "mask/colmap/images.txt",
                           "mask/colmap/points3D.txt", "mask/rig_topdown.svg"}) {
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
}

TEST(CamerasWithoutPose, ListsThemCommaSeparated) {
  EXPECT_EQ(CamerasWithoutPose(ThreeCameraResult().rig), "cam2");
  Rig all = ThreeCameraResult().rig;
  all.cameras[2].cam_from_rig = Rigid3d();
  EXPECT_EQ(CamerasWithoutPose(all), "");
}

}  // namespace
}  // namespace rigsim
