#include "rigs/rig_import.h"

#include <algorithm>
#include <cstdio>
#include <string>

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "exports/colmap.h"
#include "exports/kalibr.h"
#include "geometry/json_io.h"
#include "rigs/rig_spec.h"
#include "testing/expect_error.h"
#include "testing/temp_dir.h"

namespace rigsim {
namespace {

namespace fs = std::filesystem;

Rigid3d Pose(double ax, double ay, double az, const Eigen::Vector3d& t) {
  const Eigen::Quaterniond q = Eigen::AngleAxisd(ax, Eigen::Vector3d::UnitX()) * Eigen::AngleAxisd(ay, Eigen::Vector3d::UnitY()) *
                               Eigen::AngleAxisd(az, Eigen::Vector3d::UnitZ());
  return Rigid3d(q, t);
}

RigCamera Cam(const std::string& name, Camera camera, const Rigid3d& cam_from_rig) {
  RigCamera c;
  c.name = name;
  c.camera = std::move(camera);
  c.cam_from_rig = cam_from_rig;
  return c;
}

// Cameras of every model rigsim has, none at the rig's origin.
Rig MixedRig(bool with_full_opencv) {
  Rig rig;
  rig.cameras.push_back(Cam("front", Camera(CameraModelId::kOpenCV, 640, 480, {500, 510, 319.5, 239.5, -0.2, 0.05, 0.001, -0.002}),
                            Pose(0.1, -0.3, 0.05, {0.1, 0.0, 0.02})));
  rig.cameras.push_back(Cam("left", Camera(CameraModelId::kPinhole, 800, 600, {600, 601, 401.25, 298.0}),
                            Pose(-0.05, 0.4, 0.0, {-0.2, 0.01, 0.0})));
  rig.cameras.push_back(Cam("side", Camera(CameraModelId::kOpenCVFisheye, 1024, 1000, {300, 301, 511.5, 499.5, 0.01, -0.02, 0.003, -0.001}),
                            Pose(0.0, 1.6, 0.1, {0.0, 0.3, -0.5})));
  if (with_full_opencv) {
    rig.cameras.push_back(Cam("rear", Camera(CameraModelId::kFullOpenCV, 1936, 1216,
                                             {1000, 1001, 967.5, 607.5, -0.1, 0.02, 0.0005, -0.0003, 0.001, 0.01, 0.002, 0.0001}),
                              Pose(0.02, 3.1, -0.01, {0.05, 0.2, -2.0})));
  }
  return rig;
}

// The rig re-expressed with the first camera's frame as the rig frame, as every import gives it.
Rig InFirstCameraFrame(Rig rig) {
  const Rigid3d rig_from_cam0 = rig.cameras[0].cam_from_rig->Inverse();
  for (RigCamera& c : rig.cameras) c.cam_from_rig = *c.cam_from_rig * rig_from_cam0;
  return rig;
}

void ExpectSameRig(const Rig& expected, const Rig& read, double tolerance = 1e-9) {
  ASSERT_EQ(read.cameras.size(), expected.cameras.size());
  for (size_t i = 0; i < expected.cameras.size(); ++i) {
    const RigCamera& e = expected.cameras[i];
    const RigCamera& r = read.cameras[i];
    SCOPED_TRACE(e.name);
    EXPECT_EQ(r.name, e.name);
    EXPECT_EQ(r.camera.model(), e.camera.model());
    EXPECT_EQ(r.camera.width(), e.camera.width());
    EXPECT_EQ(r.camera.height(), e.camera.height());
    ASSERT_EQ(r.camera.params().size(), e.camera.params().size());
    for (size_t k = 0; k < e.camera.params().size(); ++k) EXPECT_NEAR(r.camera.params()[k], e.camera.params()[k], tolerance) << k;
    ASSERT_TRUE(r.cam_from_rig.has_value());
    EXPECT_LT((r.cam_from_rig->RotationMatrix() - e.cam_from_rig->RotationMatrix()).cwiseAbs().maxCoeff(), tolerance);
    EXPECT_LT((r.cam_from_rig->translation - e.cam_from_rig->translation).cwiseAbs().maxCoeff(), tolerance);
  }
}

json_io::Json PoseXyz(const Rigid3d& pose) {  // DGP's Pose
  const Eigen::Quaterniond& q = pose.rotation;
  const Eigen::Vector3d& t = pose.translation;
  return {{"rotation", {{"qw", q.w()}, {"qx", q.x()}, {"qy", q.y()}, {"qz", q.z()}}},
          {"translation", {{"x", t.x()}, {"y", t.y()}, {"z", t.z()}}}};
}

// A vehicle's frame (x forward, y left, z up) with cameras looking ahead and to the left; the
// camera axes (x right, y down, z forward) in vehicle coordinates, by hand.
const Eigen::Quaterniond kVehicleFromForwardCam(0.5, -0.5, 0.5, -0.5);  // columns (0,-1,0) (0,0,-1) (1,0,0)
const Eigen::Quaterniond kVehicleFromLeftCam(0.70710678118654752, -0.70710678118654752, 0, 0);  // (1,0,0) (0,0,-1) (0,1,0)
// What the left camera, 1 m to the left of the forward one, must be in the forward camera's frame:
// its centre 1 m along -x, looking along -x: x_left = z_front, y_left = y_front, z_left = -x_front.
void ExpectLeftOfForward(const Rig& rig) {
  ASSERT_EQ(rig.cameras.size(), 2u);
  EXPECT_LT((rig.cameras[0].cam_from_rig->RotationMatrix() - Eigen::Matrix3d::Identity()).norm(), 1e-12);
  EXPECT_LT(rig.cameras[0].cam_from_rig->translation.norm(), 1e-12);
  Eigen::Matrix3d r;
  r << 0, 0, 1, 0, 1, 0, -1, 0, 0;
  EXPECT_LT((rig.cameras[1].cam_from_rig->RotationMatrix() - r).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_LT((rig.cameras[1].cam_from_rig->translation - Eigen::Vector3d(0, 0, -1)).norm(), 1e-12);
  EXPECT_LT((rig.cameras[1].cam_from_rig->SourceOriginInTarget() - Eigen::Vector3d(-1, 0, 0)).norm(), 1e-12);
}

TEST(RigImport, KalibrCamchainRoundTrips) {
  const TempDir dir;
  const Rig rig = MixedRig(false);
  WriteKalibrCamchain(rig, dir / "camchain.yaml");
  EXPECT_EQ(DetectRigFileFormat(dir / "camchain.yaml"), RigFileFormat::kKalibr);
  ExpectSameRig(InFirstCameraFrame(rig), ReadRigFile((dir / "camchain.yaml").string()));
}

TEST(RigImport, KalibrChainsEachCameraFromThePreviousOne) {
  const TempDir dir;
  // A stereo pair and a third camera 0.12 m further right, as Kalibr writes T_cn_cnm1 =
  // cam_n_from_cam_{n-1}; no rostopic, so the cameras take their keys.
  const std::string intrinsics = "  camera_model: pinhole\n  intrinsics: [400, 400, 320, 240]\n  distortion_model: radtan\n"
                                 "  distortion_coeffs: [0, 0, 0, 0]\n  resolution: [640, 480]\n";
  const std::string chain = "  T_cn_cnm1:\n  - [1, 0, 0, -0.12]\n  - [0, 1, 0, 0]\n  - [0, 0, 1, 0]\n  - [0, 0, 0, 1]\n";
  WriteFile(dir / "camchain.yaml", "cam0:\n" + intrinsics + "cam1:\n" + chain + intrinsics + "cam2:\n" + chain +
                                       "  camera_model: pinhole\n  intrinsics: [300, 300, 320, 240]\n  distortion_model: equidistant\n"
                                       "  distortion_coeffs: [0.1, 0.01, 0, 0]\n  resolution: [640, 480]\n");
  const Rig rig = ReadRigFile((dir / "camchain.yaml").string());
  ASSERT_EQ(rig.cameras.size(), 3u);
  EXPECT_EQ(rig.cameras[1].name, "cam1");
  EXPECT_EQ(rig.cameras[0].camera.model(), CameraModelId::kPinhole);  // radtan with zero coefficients
  EXPECT_EQ(rig.cameras[2].camera.model(), CameraModelId::kOpenCVFisheye);
  EXPECT_DOUBLE_EQ(rig.cameras[2].camera.params()[4], 0.1);
  EXPECT_LT((rig.cameras[1].cam_from_rig->SourceOriginInTarget() - Eigen::Vector3d(0.12, 0, 0)).norm(), 1e-12);
  EXPECT_LT((rig.cameras[2].cam_from_rig->SourceOriginInTarget() - Eigen::Vector3d(0.24, 0, 0)).norm(), 1e-12);
}

// COLMAP 3.12's rigs.txt of a rig whose reference sensor is camera 1 (the ids of cameras.txt).
std::string RigsTxt(const Rig& rig) {
  std::string text = "# Rig calib list with one line of data per calib:\n1 " + std::to_string(rig.cameras.size()) + " CAMERA 1";
  const Rigid3d rig_from_ref = rig.cameras[0].cam_from_rig->Inverse();
  for (size_t i = 1; i < rig.cameras.size(); ++i) {
    const Rigid3d cam_from_ref = *rig.cameras[i].cam_from_rig * rig_from_ref;
    const Eigen::Quaterniond& q = cam_from_ref.rotation;
    const Eigen::Vector3d& t = cam_from_ref.translation;
    char line[400];
    std::snprintf(line, sizeof line, " CAMERA %zu 1 %.17g %.17g %.17g %.17g %.17g %.17g %.17g", i + 1, q.w(), q.x(), q.y(), q.z(),
                  t.x(), t.y(), t.z());
    text += line;
  }
  return text + "\n2 1 CAMERA 9\n";  // a camera outside the rig has a rig of its own
}

FramesFile OneFrame() {
  FramesFile frames;
  frames.frames.push_back({"000000", Pose(0.02, 0.5, 0.0, {1.0, -1.6, 3.0}), 0.0});
  return frames;
}

TEST(RigImport, ColmapRigsTxtRoundTrips) {
  const TempDir dir;
  const Rig rig = MixedRig(true);
  WriteColmapModel(rig, OneFrame(), dir / "model");  // cameras.txt, images.txt named <camera>/<frame>.png
  WriteFile(dir / "model" / "rigs.txt", RigsTxt(rig));
  ExpectSameRig(InFirstCameraFrame(rig), ReadRigFile((dir / "model").string()));
  ExpectSameRig(InFirstCameraFrame(rig), ReadRigFile((dir / "model" / "rigs.txt").string()));
}

TEST(RigImport, ColmapRigConfigRoundTrips) {
  const TempDir dir;
  const Rig rig = MixedRig(true);
  WriteColmapModel(rig, OneFrame(), dir);
  json_io::Json cameras = json_io::Json::array();
  const Rigid3d rig_from_ref = rig.cameras[0].cam_from_rig->Inverse();
  for (size_t i = 0; i < rig.cameras.size(); ++i) {
    json_io::Json c = {{"image_prefix", rig.cameras[i].name + "/"}};
    if (i == 0) {
      c["ref_sensor"] = true;
    } else {
      const Rigid3d cam_from_ref = *rig.cameras[i].cam_from_rig * rig_from_ref;
      const Eigen::Quaterniond& q = cam_from_ref.rotation;
      c["cam_from_rig_rotation"] = {q.w(), q.x(), q.y(), q.z()};
      c["cam_from_rig_translation"] = {cam_from_ref.translation.x(), cam_from_ref.translation.y(), cam_from_ref.translation.z()};
    }
    cameras.push_back(c);
  }
  // The reference camera listed last: it still comes first, its frame the rig's.
  std::rotate(cameras.begin(), cameras.begin() + 1, cameras.end());
  WriteFile(dir / "rig_config.json", json_io::Json::array({{{"cameras", cameras}}}).dump(1));
  EXPECT_EQ(DetectRigFileFormat(dir / "rig_config.json"), RigFileFormat::kColmapRigConfig);
  ExpectSameRig(InFirstCameraFrame(rig), ReadRigFile((dir / "rig_config.json").string()));
}

TEST(RigImport, ColmapQuaternionIsWFirstAndPixelCentresShiftByHalf) {
  const TempDir dir;
  WriteFile(dir / "cameras.txt", "# Camera list\n1 SIMPLE_RADIAL 640 480 500 320 240 -0.1\n2 PINHOLE 640 480 400 401 320 240\n");
  // Camera 2 turned 90 deg about y from the reference, its centre 0.5 m to the reference's right.
  WriteFile(dir / "rigs.txt", "1 2 CAMERA 1 CAMERA 2 1 0.70710678118654757 0 0.70710678118654757 0 0 0 0.5\n");
  WriteFile(dir / "images.txt", "1 1 0 0 0 0 0 0 1 left/0.png\n\n2 1 0 0 0 0 0 0 2 right/0.png\n\n");
  const Rig rig = ReadRigFile((dir / "rigs.txt").string());
  ASSERT_EQ(rig.cameras.size(), 2u);
  EXPECT_EQ(rig.cameras[0].name, "left");
  EXPECT_EQ(rig.cameras[1].name, "right");
  EXPECT_EQ(rig.cameras[0].camera.model(), CameraModelId::kOpenCV);
  EXPECT_EQ(rig.cameras[0].camera.params(), (std::vector<double>{500, 500, 319.5, 239.5, -0.1, 0, 0, 0}));
  EXPECT_EQ(rig.cameras[1].camera.params(), (std::vector<double>{400, 401, 319.5, 239.5}));
  // x_cam = R x_rig + t with R turning the rig's +x onto the camera's -z.
  EXPECT_LT((rig.cameras[1].cam_from_rig->rotation * Eigen::Vector3d::UnitX() - Eigen::Vector3d(0, 0, -1)).norm(), 1e-12);
  EXPECT_LT((rig.cameras[1].cam_from_rig->SourceOriginInTarget() - Eigen::Vector3d(0.5, 0, 0)).norm(), 1e-12);
}

// A DGP scene folder: SCENE/calibration/<hash>.json and SCENE/scene_<hash>.json with the image
// sizes, the lidar first (the vehicle frame's sensor here, as in DDAD).
fs::path WriteDgpScene(const fs::path& scene, const std::vector<std::pair<std::string, Rigid3d>>& vehicle_from_cam,
                       const std::vector<json_io::Json>& intrinsics, const std::vector<std::pair<int, int>>& sizes) {
  json_io::Json calibration = {{"names", {"LIDAR"}},
                      {"extrinsics", {PoseXyz(Rigid3d())}},
                      {"intrinsics", {{{"fx", 0.0}, {"fy", 0.0}, {"cx", 0.0}, {"cy", 0.0}, {"skew", 0.0}}}}};
  json_io::Json data = json_io::Json::array();
  for (size_t i = 0; i < vehicle_from_cam.size(); ++i) {
    calibration["names"].push_back(vehicle_from_cam[i].first);
    calibration["extrinsics"].push_back(PoseXyz(vehicle_from_cam[i].second));
    calibration["intrinsics"].push_back(intrinsics[i]);
    data.push_back({{"id", {{"name", vehicle_from_cam[i].first}, {"index", "0"}}},
                    {"datum", {{"image", {{"width", sizes[i].first}, {"height", sizes[i].second}, {"channels", 3}}}}}});
  }
  fs::create_directories(scene / "calibration");
  WriteFile(scene / "calibration" / "c0e1.json", calibration.dump(1));
  WriteFile(scene / "scene_a8dc.json", json_io::Json{{"data", data}, {"samples", json_io::Json::array()}}.dump(1));
  return scene / "calibration" / "c0e1.json";
}

TEST(RigImport, DgpCalibrationRoundTrips) {
  const TempDir dir;
  Rig rig = MixedRig(true);
  rig.cameras.erase(rig.cameras.begin() + 2);  // DGP's fisheye models are not read
  const Rigid3d vehicle_from_rig = Pose(0.3, -0.2, 1.1, {1.5, 0.1, 1.6});
  std::vector<std::pair<std::string, Rigid3d>> poses;
  std::vector<json_io::Json> intrinsics;
  std::vector<std::pair<int, int>> sizes;
  for (const RigCamera& c : rig.cameras) {
    poses.push_back({c.name, vehicle_from_rig * c.cam_from_rig->Inverse()});
    const std::vector<double>& p = c.camera.params();
    json_io::Json in = {{"fx", p[0]}, {"fy", p[1]}, {"cx", p[2]}, {"cy", p[3]}, {"skew", 0.0}, {"fov", 0.0}, {"fisheye", 0}};
    const char* keys[] = {"k1", "k2", "p1", "p2", "k3", "k4", "k5", "k6"};
    for (size_t k = 4; k < p.size(); ++k) in[keys[k - 4]] = p[k];
    intrinsics.push_back(in);
    sizes.push_back({c.camera.width(), c.camera.height()});
  }
  const fs::path calibration = WriteDgpScene(dir / "scene_01", poses, intrinsics, sizes);
  EXPECT_EQ(DetectRigFileFormat(calibration), RigFileFormat::kDgp);
  ExpectSameRig(InFirstCameraFrame(rig), ReadRigFile(calibration.string()));
}

TEST(RigImport, DgpExtrinsicsAreTheSensorsPoseInTheVehicle) {
  const TempDir dir;
  const json_io::Json pinhole = {{"fx", 1000.0}, {"fy", 1000.0}, {"cx", 960.0}, {"cy", 600.0}};
  const fs::path calibration =
      WriteDgpScene(dir / "scene", {{"CAMERA_01", Rigid3d(kVehicleFromForwardCam, {1.5, 0, 1.6})}, {"CAMERA_05", Rigid3d(kVehicleFromLeftCam, {1.5, 1, 1.6})}},
                    {pinhole, pinhole}, {{1936, 1216}, {1936, 1216}});
  const Rig rig = ReadRigFile(calibration.string());
  EXPECT_EQ(rig.cameras[0].name, "CAMERA_01");
  EXPECT_EQ(rig.cameras[0].camera.model(), CameraModelId::kPinhole);
  EXPECT_EQ(rig.cameras[1].camera.width(), 1936);
  ExpectLeftOfForward(rig);
}

// nuScenes tables: calibrated_sensor.json (with a lidar), sensor.json and sample_data.json.
void WriteNuScenes(const fs::path& dir, const std::vector<std::pair<std::string, Rigid3d>>& ego_from_cam,
                   const std::vector<Camera>& cameras) {
  json_io::Json calibrated = json_io::Json::array(), sensors = json_io::Json::array(), samples = json_io::Json::array();
  calibrated.push_back({{"token", "cs_lidar"}, {"sensor_token", "s_lidar"}, {"translation", {0.9, 0, 1.8}},
                        {"rotation", {0.7, 0, 0, 0.7}}, {"camera_intrinsic", json_io::Json::array()}});
  sensors.push_back({{"token", "s_lidar"}, {"channel", "LIDAR_TOP"}, {"modality", "lidar"}});
  for (size_t i = 0; i < cameras.size(); ++i) {
    const std::vector<double>& p = cameras[i].params();
    const Eigen::Quaterniond& q = ego_from_cam[i].second.rotation;
    const Eigen::Vector3d& t = ego_from_cam[i].second.translation;
    const std::string n = std::to_string(i);
    calibrated.push_back({{"token", "cs" + n}, {"sensor_token", "s" + n}, {"translation", {t.x(), t.y(), t.z()}},
                          {"rotation", {q.w(), q.x(), q.y(), q.z()}},
                          {"camera_intrinsic", {{p[0], 0.0, p[2]}, {0.0, p[1], p[3]}, {0.0, 0.0, 1.0}}}});
    sensors.push_back({{"token", "s" + n}, {"channel", ego_from_cam[i].first}, {"modality", "camera"}});
    samples.push_back({{"token", "sd" + n}, {"calibrated_sensor_token", "cs" + n}, {"width", cameras[i].width()},
                       {"height", cameras[i].height()}, {"is_key_frame", true}});
  }
  WriteFile(dir / "calibrated_sensor.json", calibrated.dump(1));
  WriteFile(dir / "sensor.json", sensors.dump(1));
  WriteFile(dir / "sample_data.json", samples.dump(1));
}

TEST(RigImport, NuScenesCalibratedSensorsRoundTrip) {
  const TempDir dir;
  Rig rig;
  rig.cameras.push_back(Cam("CAM_FRONT", Camera(CameraModelId::kPinhole, 1600, 900, {1266.4, 1266.5, 816.25, 491.5}), Pose(0.01, 0, 0, {0, 0, 0.1})));
  rig.cameras.push_back(Cam("CAM_BACK", Camera(CameraModelId::kPinhole, 1600, 900, {809.2, 809.3, 829.2, 481.75}), Pose(0, 3.1, 0.02, {0.01, 0.04, -1.6})));
  rig.cameras.push_back(Cam("CAM_FRONT_LEFT", Camera(CameraModelId::kPinhole, 1600, 900, {1272.6, 1272.5, 826.6, 479.75}), Pose(0, -0.9, 0, {0.4, 0, -0.3})));
  const Rigid3d ego_from_rig(kVehicleFromForwardCam, {1.7, 0.0, 1.5});
  // The records in another order than nuScenes' ring: the import puts CAM_FRONT first.
  std::vector<std::pair<std::string, Rigid3d>> poses;
  std::vector<Camera> cameras;
  for (int i : {2, 1, 0}) {
    poses.push_back({rig.cameras[i].name, ego_from_rig * rig.cameras[i].cam_from_rig->Inverse()});
    cameras.push_back(rig.cameras[i].camera);
  }
  WriteNuScenes(dir, poses, cameras);
  EXPECT_EQ(DetectRigFileFormat(dir / "calibrated_sensor.json"), RigFileFormat::kNuScenes);
  ExpectSameRig(InFirstCameraFrame(rig), ReadRigFile((dir / "calibrated_sensor.json").string()));
}

TEST(RigImport, NuScenesRotationIsTheSensorsPoseInTheEgoFrame) {
  const TempDir dir;
  const Camera pinhole(CameraModelId::kPinhole, 1600, 900, {1266, 1266, 800, 450});
  WriteNuScenes(dir, {{"CAM_FRONT_LEFT", Rigid3d(kVehicleFromLeftCam, {1.5, 1, 1.6})}, {"CAM_FRONT", Rigid3d(kVehicleFromForwardCam, {1.5, 0, 1.6})}},
                {pinhole, pinhole});
  const Rig rig = ReadRigFile((dir / "calibrated_sensor.json").string());
  EXPECT_EQ(rig.cameras[0].name, "CAM_FRONT");
  ExpectLeftOfForward(rig);
}

// A real-rig folder's truth_rig.json (bench/real_rigs/rig_common.py): rigsim's rig.json with each
// quaternion under "rotation", w first; make-rig --rig-file reads it as it stands.
TEST(RigImport, ARealRigFoldersTruthRigReadsAsARigJson) {
  const TempDir dir;
  const Rig rig = MixedRig(false);
  nlohmann::json truth = nlohmann::json::parse(RigToJsonText(rig));
  for (nlohmann::json& camera : truth["cameras"]) {
    nlohmann::json& pose = camera["cam_from_rig"];
    pose["rotation"] = pose["rotation_wxyz"];
    pose.erase("rotation_wxyz");
  }
  WriteFile(dir / "truth_rig.json", truth.dump(1));
  EXPECT_EQ(DetectRigFileFormat(dir / "truth_rig.json"), RigFileFormat::kRigJson);
  ExpectSameRig(rig, ReadRigFile((dir / "truth_rig.json").string()));
}

TEST(RigImport, BadFilesAreRefusedNamingTheFileAndWhy) {
  const TempDir dir;
  const auto refused = [&](const std::string& name, const std::string& text, const std::string& why) {
    WriteFile(dir / name, text);
    const std::string path = (dir / name).string();
    EXPECT_THAT([&] { ReadRigFile(path); }, ThrowsNaming<std::runtime_error>(path, why)) << name;
  };
  // Unknown formats.
  refused("notes.txt", "hello\n", "not a rig file");
  refused("other.json", R"({"frames": []})", "not a rig file");
  // Models rigsim has no equivalent of.
  refused("omni.yaml", "cam0:\n  camera_model: omni\n  intrinsics: [0.8, 400, 400, 320, 240]\n  resolution: [640, 480]\n",
          "cam0: camera_model 'omni'");
  refused("fov.yaml", "cam0:\n  camera_model: pinhole\n  intrinsics: [400, 400, 320, 240]\n  distortion_model: fov\n"
          "  distortion_coeffs: [0.9]\n  resolution: [640, 480]\n", "distortion_model 'fov'");
  fs::create_directories(dir / "fov_model");
  WriteFile(dir / "fov_model" / "rigs.txt", "1 1 CAMERA 1\n");
  refused("fov_model/cameras.txt", "1 FOV 640 480 400 400 320 240 0.9\n", "camera 1 (rig 1): model FOV has no rigsim equivalent");
  const json_io::Json pinhole = {{"fx", 1000.0}, {"fy", 1000.0}, {"cx", 960.0}, {"cy", 600.0}};
  json_io::Json double_sphere = pinhole;
  double_sphere["xi"] = -0.2;
  const fs::path ds = WriteDgpScene(dir / "ds", {{"CAMERA_01", Rigid3d()}}, {double_sphere}, {{1936, 1216}});
  EXPECT_THAT([&] { ReadRigFile(ds.string()); }, ThrowsNaming<std::runtime_error>(ds.string(), "camera 'CAMERA_01': xi is not 0"));
  refused("no_model.yaml", "cam0:\n  camera_model: pinhole\n  intrinsics: [400, 400, 320, 240]\n  distortion_coeffs: [0.1, 0, 0, 0]\n"
          "  resolution: [640, 480]\n", "cam0: distortion_coeffs without a distortion_model");
  // A pose that is not a number.
  const std::string pinhole_yaml = "  camera_model: pinhole\n  intrinsics: [400, 400, 320, 240]\n  resolution: [640, 480]\n";
  refused("infinite.yaml", "cam0:\n" + pinhole_yaml + "cam1:\n  T_cn_cnm1:\n  - [1, 0, 0, .inf]\n  - [0, 1, 0, 0]\n  - [0, 0, 1, 0]\n"
          "  - [0, 0, 0, 1]\n" + pinhole_yaml, "camera 'cam1': its pose on the rig is not finite");
  // Names rig.json would refuse.
  refused("names.json", R"([{"token": "a", "sensor_token": "s", "channel": "..", "translation": [0, 0, 0], "rotation": [1, 0, 0, 0],
      "camera_intrinsic": [[1000, 0, 800], [0, 1000, 450], [0, 0, 1]], "width": 1600, "height": 900}])",
          "camera name '..' must be non-empty and usable as a folder name");
  fs::create_directories(dir / "latin1");
  WriteFile(dir / "latin1" / "cameras.txt", "1 PINHOLE 64 48 50 50 32 24\n");
  WriteFile(dir / "latin1" / "images.txt", "1 1 0 0 0 0 0 0 1 l\xe9" "ft/0.png\n\n");
  refused("latin1/rigs.txt", "1 1 CAMERA 1\n", "a camera name is not UTF-8 text");
  // Missing fields and sizes.
  fs::create_directories(dir / "rigs_no_pose");
  WriteFile(dir / "rigs_no_pose" / "cameras.txt", "1 PINHOLE 64 48 50 50 32 24\n2 PINHOLE 64 48 50 50 32 24\n");
  refused("rigs_no_pose/rigs.txt", "1 2 CAMERA 1 CAMERA 2 0\n", "camera 2 has no pose in the rig");
  refused("calibrated_sensor.json",
          R"([{"token": "a", "sensor_token": "b", "channel": "CAM_FRONT", "rotation": [1, 0, 0, 0],
              "camera_intrinsic": [[1000, 0, 800], [0, 1000, 450], [0, 0, 1]], "width": 1600, "height": 900}])",
          "missing field 'translation'");
  refused("calibrated_sensor.json",
          R"([{"token": "a", "sensor_token": "b", "channel": "CAM_FRONT", "rotation": [1, 0, 0, 0], "translation": [0, 0, 0],
              "camera_intrinsic": [[1000, 0, 800], [0, 1000, 450], [0, 0, 1]]}])",
          "camera 'CAM_FRONT': calibrated_sensor records no image size");
  fs::remove(dir / "ds" / "scene_a8dc.json");
  EXPECT_THAT([&] { ReadRigFile(ds.string()); },
              ThrowsNaming<std::runtime_error>(ds.string(), "camera 'CAMERA_01': a DGP calibration records no image size"));
}

}  // namespace
}  // namespace rigsim
