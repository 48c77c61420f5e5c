// `rigsim make-rig --type file --rig-file` with other tools' calibration files, through the built
// binary: a Kalibr camchain and nuScenes calibrated_sensor records become the rig (in the first
// camera's frame), a file of no known format or a camera without an image size is refused naming
// the file, and nothing is written then.

#include <filesystem>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "dataset/dataset.h"
#include "exports/kalibr.h"
#include "geometry/rig.h"
#include "testing/temp_dir.h"
#include "tests/rigsim_cli.h"

namespace rigsim {
namespace {
namespace fs = std::filesystem;
using nlohmann::json;

CliResult RunRigsim(const fs::path& dir, const std::vector<std::string>& args) { return rigsim::RunRigsim(args, dir / "rigsim"); }

Rigid3d Pose(double yaw, const Eigen::Vector3d& t) { return Rigid3d(Eigen::Quaterniond(Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitY())), t); }

TEST(MakeRigImport, AKalibrCamchainIsTheRigOnItsPath) {
  const TempDir dir;
  Rig rig;
  rig.cameras.push_back({"left", Camera(CameraModelId::kOpenCV, 640, 480, {500, 501, 319.5, 239.5, -0.2, 0.05, 0.001, -0.002}),
                         Pose(0.2, {0.3, 0, 0.1}), 0.0});
  rig.cameras.push_back({"right", Camera(CameraModelId::kOpenCVFisheye, 640, 480, {300, 300, 320, 240, 0.01, -0.02, 0.003, -0.001}),
                         Pose(-0.3, {-0.2, 0.01, 0}), 0.0});
  WriteKalibrCamchain(rig, dir / "camchain.yaml");
  const CliResult r = RunRigsim(dir, {"make-rig", "--type", "file", "--rig-file", (dir / "camchain.yaml").string(), "--frames", "2",
                                      "--out", (dir / "out").string()});
  ASSERT_EQ(r.code, 0) << r.err;
  const Rig read = ReadRig(dir / "out" / "rig.json");
  ASSERT_EQ(read.cameras.size(), 2u);
  const Rigid3d rig_from_left = rig.cameras[0].cam_from_rig->Inverse();
  for (size_t i = 0; i < 2; ++i) {
    EXPECT_EQ(read.cameras[i].name, rig.cameras[i].name);
    EXPECT_EQ(read.cameras[i].camera.model(), rig.cameras[i].camera.model());
    for (size_t k = 0; k < 8; ++k) EXPECT_NEAR(read.cameras[i].camera.params()[k], rig.cameras[i].camera.params()[k], 1e-9);
    const Rigid3d expected = *rig.cameras[i].cam_from_rig * rig_from_left;  // the rig frame is the first camera's
    EXPECT_LT(RotationDifferenceDeg(read.cameras[i].cam_from_rig->rotation, expected.rotation), 1e-7);
    EXPECT_LT((read.cameras[i].cam_from_rig->translation - expected.translation).norm(), 1e-9);
  }
  EXPECT_EQ(ReadFrames(dir / "out" / "frames.json").frames.size(), 2u);
}

TEST(MakeRigImport, NuScenesRecordsBecomeTheRingFrontFirst) {
  const TempDir dir;
  // The left camera's record first; both 1 m apart, looking ahead and to the left (ego frame: x
  // forward, y left, z up).
  WriteFile(dir / "calibrated_sensor.json", R"([
    {"token": "b", "sensor_token": "sb", "channel": "CAM_FRONT_LEFT", "width": 1600, "height": 900,
     "translation": [1.5, 1.0, 1.6], "rotation": [0.7071067811865476, -0.7071067811865476, 0, 0],
     "camera_intrinsic": [[1260, 0, 800], [0, 1260, 450], [0, 0, 1]]},
    {"token": "a", "sensor_token": "sa", "channel": "CAM_FRONT", "width": 1600, "height": 900,
     "translation": [1.5, 0.0, 1.6], "rotation": [0.5, -0.5, 0.5, -0.5],
     "camera_intrinsic": [[1266, 0, 816], [0, 1266, 491], [0, 0, 1]]}])");
  const CliResult r = RunRigsim(dir, {"make-rig", "--type", "file", "--rig-file", (dir / "calibrated_sensor.json").string(),
                                      "--out", (dir / "out").string()});
  ASSERT_EQ(r.code, 0) << r.err;
  const Rig rig = ReadRig(dir / "out" / "rig.json");
  ASSERT_EQ(rig.cameras.size(), 2u);
  EXPECT_EQ(rig.cameras[0].name, "CAM_FRONT");
  EXPECT_EQ(rig.cameras[0].camera.params(), (std::vector<double>{1266, 1266, 816, 491}));
  // The left camera sits 1 m along the front camera's -x and looks along it.
  EXPECT_LT((rig.cameras[1].cam_from_rig->SourceOriginInTarget() - Eigen::Vector3d(-1, 0, 0)).norm(), 1e-9);
  EXPECT_LT((rig.cameras[1].cam_from_rig->rotation.conjugate() * Eigen::Vector3d::UnitZ() - Eigen::Vector3d(-1, 0, 0)).norm(), 1e-9);
}

TEST(MakeRigImport, AFileOfNoKnownFormatOrWithoutImageSizesIsRefusedNamingIt) {
  const TempDir dir;
  WriteFile(dir / "notes.txt", "not a rig\n");
  const CliResult unknown = RunRigsim(dir, {"make-rig", "--type", "file", "--rig-file", (dir / "notes.txt").string(), "--out",
                                            (dir / "out").string()});
  EXPECT_NE(unknown.code, 0);
  EXPECT_NE(unknown.err.find((dir / "notes.txt").string() + ": not a rig file"), std::string::npos) << unknown.err;
  EXPECT_NE(unknown.err.find("Kalibr camchain.yaml"), std::string::npos) << "the formats read are listed: " << unknown.err;
  WriteFile(dir / "records.json", R"([{"token": "a", "sensor_token": "s", "channel": "CAM_FRONT", "translation": [0, 0, 0],
    "rotation": [1, 0, 0, 0], "camera_intrinsic": [[1266, 0, 816], [0, 1266, 491], [0, 0, 1]]}])");
  const CliResult no_size = RunRigsim(dir, {"make-rig", "--type", "file", "--rig-file", (dir / "records.json").string(), "--out",
                                            (dir / "out").string()});
  EXPECT_NE(no_size.code, 0);
  EXPECT_NE(no_size.err.find((dir / "records.json").string() + ": camera 'CAM_FRONT': calibrated_sensor records no image size"),
            std::string::npos)
      << no_size.err;
  EXPECT_FALSE(fs::exists(dir / "out"));
  EXPECT_TRUE(StagingFolders(dir / "out").empty());
}

}  // namespace
}  // namespace rigsim
