#include "evaluation/rig_estimate.h"

#include <filesystem>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "evaluation/rig_scores.h"
#include "exports/colmap.h"
#include "exports/kalibr.h"
#include "testing/expect_error.h"
#include "testing/temp_dir.h"

namespace rigsim {
namespace {

namespace fs = std::filesystem;

// A ring of three cameras (the middle one distorted) and two frames of a rig moving forward.
Rig Truth() {
  Rig rig;
  const Camera pinhole(CameraModelId::kPinhole, 64, 48, {50, 50, 31.5, 23.5});
  const Camera opencv(CameraModelId::kOpenCV, 64, 48, {50, 50, 31.5, 23.5, -0.2, 0.05, 0, 0});
  for (int c = 0; c < 3; ++c) {
    const Eigen::Quaterniond r(Eigen::AngleAxisd(DegToRad(-50.0 * c), Eigen::Vector3d::UnitY()));
    const Eigen::Vector3d centre(0.5 * std::sin(DegToRad(50.0 * c)), 0.0, 0.5 * std::cos(DegToRad(50.0 * c)));
    rig.cameras.push_back({"cam" + std::to_string(c), c == 1 ? opencv : pinhole, Rigid3d(r, -(r * centre))});
  }
  return rig;
}

FramesFile Frames() {
  FramesFile f;
  for (int k = 0; k < 2; ++k) {
    f.frames.push_back({"00000" + std::to_string(k),
                        Rigid3d(Eigen::Quaterniond(Eigen::AngleAxisd(0.1 * k, Eigen::Vector3d::UnitY())),
                                Eigen::Vector3d(0, 0, -2.0 * k)),
                        0.1 * k});
  }
  return f;
}

TEST(RigEstimate, AColmapModelOfTheTruthScoresPerfectly) {
  const TempDir dir;
  const Rig truth = Truth();
  const FramesFile frames = Frames();
  // The export writes what COLMAP writes; a model at another scale and in another world frame
  // (as COLMAP's are) must read back as the same rig.
  Rig scaled = truth;
  for (RigCamera& c : scaled.cameras) c.cam_from_rig->translation *= 3.0;
  FramesFile moved = frames;
  for (Frame& f : moved.frames) {
    f.rig_from_world = *f.rig_from_world * Rigid3d(Eigen::Quaterniond(Eigen::AngleAxisd(1.0, Eigen::Vector3d::UnitX())),
                                                   Eigen::Vector3d(1, 2, 3));
    f.rig_from_world->translation *= 3.0;
  }
  WriteColmapModel(scaled, moved, dir / "sparse" / "1");
  // A smaller sub-model beside it: the larger one is read.
  FramesFile first = moved;
  first.frames.resize(1);
  WriteColmapModel(scaled, first, dir / "sparse" / "0");
  const std::vector<RigEstimate> e = ReadRigEstimates(dir / "sparse", truth, frames);
  ASSERT_EQ(e.size(), 1u);
  EXPECT_EQ(e[0].method, "colmap");
  EXPECT_FALSE(e[0].metric);
  const RigScores s = ScoreRig(truth, e[0]);
  EXPECT_EQ(s.cameras_posed, 3);
  EXPECT_NEAR(*s.max_rotation_error_deg, 0.0, 1e-6);
  EXPECT_NEAR(*s.max_direction_error_deg, 0.0, 1e-6);
  EXPECT_NEAR(s.scale, 1.0 / 3.0, 1e-9);
}

TEST(RigEstimate, ColmapImagesNotRegisteredLeaveTheirCameraOutWithANote) {
  const Rig truth = Truth();
  const FramesFile frames = Frames();
  std::vector<std::pair<std::string, Rigid3d>> images;
  for (const Frame& f : frames.frames) {
    for (int c : {0, 1}) images.push_back({truth.cameras[c].name + "/" + f.name + ".png", *truth.cameras[c].cam_from_rig * *f.rig_from_world});
  }
  images.push_back({"other/000000.png", Rigid3d()});
  const RigEstimate e = RigEstimateFromColmap(images, truth, frames);
  EXPECT_TRUE(e.cam_from_rig[1].has_value());
  EXPECT_FALSE(e.cam_from_rig[2].has_value());
  ASSERT_EQ(e.notes.size(), 2u);
  EXPECT_EQ(e.notes[0], "1 images of the model are not <camera>/<frame> of the dataset");
  EXPECT_EQ(e.notes[1], "COLMAP registered 4 of 6 images");
}

TEST(RigEstimate, ColmapImagesTxtKeepsItsLinePairsAndRefusesGarbage) {
  const TempDir dir;
  WriteFile(dir / "images.txt",
            "# comment\n"
            "3 1 0 0 0 0.5 0 0 2 cam1/000000.png\n"
            "10.0 20.0 -1 11.0 21.0 7\n"
            "# between\n"
            "4 0 1 0 0 0 0 1 1 my cam/000001.JPG\n"
            "\n");
  const std::vector<ColmapImage> images = ReadColmapImages(dir / "images.txt");
  ASSERT_EQ(images.size(), 2u);
  EXPECT_EQ(images[0].image_id, 3);
  EXPECT_EQ(images[0].camera_id, 2);
  EXPECT_EQ(images[0].name, "cam1/000000.png");
  EXPECT_NEAR(images[0].cam_from_world.translation.x(), 0.5, 0);
  EXPECT_EQ(images[1].name, "my cam/000001.JPG");  // names may hold spaces
  WriteFile(dir / "images.txt", "1 1 0 0\n\n");
  EXPECT_THAT([&] { ReadColmapImages(dir / "images.txt"); }, ThrowsWith<std::runtime_error>("images.txt:1: not an image line"));
}

TEST(RigEstimate, KalibrCamchainReadsBackWhatTheExportWrote) {
  const TempDir dir;
  const Rig truth = Truth();
  WriteKalibrCamchain(truth, dir / "camchain.yaml");
  const std::vector<RigEstimate> e = ReadRigEstimates(dir / "camchain.yaml", truth, Frames());
  ASSERT_EQ(e.size(), 1u);
  EXPECT_TRUE(e[0].metric);
  const RigScores s = ScoreRig(truth, e[0]);
  EXPECT_NEAR(*s.max_rotation_error_deg, 0.0, 1e-6);
  EXPECT_NEAR(*s.max_position_error_m, 0.0, 1e-9);
  // A camera the dataset does not have is named, with a suggestion.
  Rig renamed = truth;
  renamed.cameras[2].name = "cma2";
  WriteKalibrCamchain(renamed, dir / "camchain.yaml");
  EXPECT_THAT([&] { ReadRigEstimates(dir / "camchain.yaml", truth, Frames()); },
              ThrowsWith<std::runtime_error>("cam2: camera 'cma2' is not in the dataset's rig (cam0, cam1, cam2) (did you mean 'cam2'?)"));
}

TEST(RigEstimate, ACalibrationFolderGivesOneEstimatePerModeWithItsRotationOnlyCameras) {
  const TempDir dir;
  const Rig truth = Truth();
  Rig estimate = truth;
  estimate.cameras[2].cam_from_rig.reset();
  for (const char* mode : {"none", "mask"}) {
    fs::create_directories(dir / mode);
    WriteRig(estimate, dir / mode / "rig.json");
  }
  const Eigen::Quaterniond q = truth.cameras[2].cam_from_rig->rotation;
  const nlohmann::json cam2 = {{"name", "cam2"},
                               {"position_known", false},
                               {"rotation_wxyz", {q.w(), q.x(), q.y(), q.z()}},
                               {"rotation_std_deg", 0.02},
                               {"direction_std_deg", nullptr}};
  const nlohmann::json cam1 = {{"name", "cam1"}, {"rotation_std_deg", 0.01}, {"direction_std_deg", 0.3}};
  const nlohmann::json rig = {{"cameras", {cam1, cam2}}, {"summary", {{"metric_scale", true}}}};
  WriteFile(dir / "evaluation.json", nlohmann::ordered_json{{"methods", {{"none", {{"rig", rig}}}, {"mask", {{"rig", rig}}}}}}.dump());
  const std::vector<RigEstimate> e = ReadRigEstimates(dir, truth, Frames());
  ASSERT_EQ(e.size(), 2u);
  EXPECT_EQ(e[0].method, "none");  // in the order calibrate ran the modes
  EXPECT_EQ(e[1].method, "mask");
  EXPECT_TRUE(e[0].metric);
  EXPECT_FALSE(e[0].cam_from_rig[2].has_value());
  ASSERT_TRUE(e[0].rotation_only[2].has_value());
  // The deviations the calibration stated come back with it.
  EXPECT_EQ(e[0].rotation_std_deg[1], 0.01);
  EXPECT_EQ(e[0].direction_std_deg[1], 0.3);
  EXPECT_EQ(e[0].rotation_std_deg[2], 0.02);
  EXPECT_FALSE(e[0].direction_std_deg[2].has_value());
  EXPECT_FALSE(e[0].rotation_std_deg[0].has_value());
  const RigScores s = ScoreRig(truth, e[1]);
  EXPECT_EQ(s.cameras_rotation_only, 1);
  EXPECT_NEAR(*s.cameras[2].rotation_error_deg, 0.0, 1e-6);
  // The same folder forced to be scored without a metric scale.
  EXPECT_FALSE(ReadRigEstimates(dir, truth, Frames(), EstimateScale::kFit)[0].metric);
}

// evaluation.json's open_axis and centre_across_axis (in the calibration's rig frame) come back as
// the camera's open-axis part, and are scored as such.
TEST(RigEstimate, ACalibrationFolderGivesItsCamerasPlacedButForOneAxis) {
  const TempDir dir;
  const Rig truth = Truth();
  Rig estimate = truth;
  estimate.cameras[2].cam_from_rig.reset();
  fs::create_directories(dir / "none");
  WriteRig(estimate, dir / "none" / "rig.json");
  // A point on the line through cam2's centre along the axis, seen from cam0's centre (not the rig
  // origin here) turned 2 deg about the axis: the direction across the axis from camera 0 is 2 deg off.
  const Eigen::Vector3d up = Eigen::Vector3d::UnitY();
  const Eigen::Vector3d cam0 = truth.cameras[0].cam_from_rig->SourceOriginInTarget();
  const Eigen::Vector3d from_cam0 = truth.cameras[2].cam_from_rig->SourceOriginInTarget() - cam0;
  const Eigen::Vector3d across = cam0 + Eigen::AngleAxisd(DegToRad(2.0), up) * (from_cam0 - up * up.dot(from_cam0));
  const Eigen::Quaterniond q = truth.cameras[2].cam_from_rig->rotation;
  nlohmann::json cam2 = {{"name", "cam2"},
                         {"position_known", false},
                         {"rotation_wxyz", {q.w(), q.x(), q.y(), q.z()}},
                         {"open_axis", {0.0, -2.0, 0.0}},  // read as a unit axis
                         {"centre_across_axis", {across.x(), across.y(), across.z()}}};
  const auto write = [&] {
    const nlohmann::json rig = {{"cameras", {cam2}}, {"summary", {{"metric_scale", false}}}};
    WriteFile(dir / "evaluation.json", nlohmann::json{{"methods", {{"none", {{"rig", rig}}}}}}.dump());
  };
  write();
  const std::vector<RigEstimate> e = ReadRigEstimates(dir, truth, Frames());
  ASSERT_EQ(e.size(), 1u);
  ASSERT_TRUE(e[0].open_axis[2].has_value());
  EXPECT_TRUE(e[0].open_axis[2]->axis.isApprox(-up));
  EXPECT_FALSE(e[0].open_axis[1].has_value());
  const RigScores s = ScoreRig(truth, e[0]);
  EXPECT_EQ(s.cameras_open_axis, 1);
  EXPECT_EQ(s.cameras_rotation_only, 0);
  EXPECT_NEAR(s.cameras[2].across_axis_direction_error_deg.value(), 2.0, 1e-9);
  // A malformed part is refused naming the file and the camera.
  cam2["open_axis"] = {0.0, 0.0, 0.0};
  write();
  EXPECT_THAT([&] { ReadRigEstimates(dir, truth, Frames()); },
              ThrowsWith<std::runtime_error>("evaluation.json: camera 'cam2': \"open_axis\" is not a direction"));
  cam2["open_axis"] = {0.0, 1.0, 0.0};
  cam2.erase("centre_across_axis");
  write();
  EXPECT_THAT([&] { ReadRigEstimates(dir, truth, Frames()); },
              ThrowsWith<std::runtime_error>("evaluation.json: camera 'cam2': \"centre_across_axis\" is not 3 numbers"));
}

TEST(RigEstimate, AnUnknownFileIsRefusedSayingWhatIsRead) {
  const TempDir dir;
  WriteFile(dir / "poses.txt", "1 2 3\n");
  EXPECT_THAT([&] { ReadRigEstimates(dir / "poses.txt", Truth(), Frames()); },
              ThrowsWith<std::runtime_error>("not an estimate rigsim reads"));
  EXPECT_THROW(ReadRigEstimates(dir / "missing.json", Truth(), Frames()), std::runtime_error);
}

}  // namespace
}  // namespace rigsim
