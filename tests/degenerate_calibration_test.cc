// Calibration input that cannot give a pose must give a diagnosis, never a confident wrong
// answer: featureless images, every feature masked away, views that share nothing, a pure
// rotation, a planar scene. Each case renders a small dataset and runs the real pipeline.
#include <algorithm>
#include <filesystem>
#include <random>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "dataset/dataset.h"
#include "dataset/label_image.h"
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

// A square of side `size` in the plane y = height (world, +Y up), facing up, optionally textured
// with seeded noise rich in corners.
Scene GroundPlane(double size, bool textured) {
  Scene scene;
  scene.source = "ground-plane";
  SceneMesh m;
  m.name = "ground";
  m.class_id = 7;  // road
  m.instance_id = 1;
  m.material = 0;
  const float h = static_cast<float>(size / 2);
  m.positions = {{-h, 0, -h}, {h, 0, -h}, {h, 0, h}, {-h, 0, h}};
  m.normals.assign(4, Eigen::Vector3f(0, 1, 0));
  m.texcoords = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  m.indices = {0, 2, 1, 0, 3, 2};
  scene.meshes.push_back(m);
  Material mat;
  mat.base_color_factor = Eigen::Vector4f(0.6f, 0.6f, 0.6f, 1.0f);
  if (textured) {
    Texture tex;
    tex.width = tex.height = 1024;
    tex.rgba.assign(size_t(tex.width) * tex.height * 4, 255);
    std::mt19937 rng(5);
    std::uniform_int_distribution<int> value(0, 255), pos(0, 1023), radius(2, 14);
    // Random discs of random grey on a mid-grey: corners and blobs at several scales.
    for (size_t i = 0; i < tex.rgba.size(); i += 4) tex.rgba[i] = tex.rgba[i + 1] = tex.rgba[i + 2] = 128;
    for (int k = 0; k < 12000; ++k) {
      const int cx = pos(rng), cy = pos(rng), r = radius(rng);
      const uint8_t v = static_cast<uint8_t>(value(rng));
      for (int y = std::max(0, cy - r); y < std::min(tex.height, cy + r); ++y)
        for (int x = std::max(0, cx - r); x < std::min(tex.width, cx + r); ++x)
          if ((x - cx) * (x - cx) + (y - cy) * (y - cy) < r * r)
            for (int c = 0; c < 3; ++c) tex.rgba[(size_t(y) * tex.width + x) * 4 + c] = v;
    }
    scene.textures.push_back(tex);
    mat.base_color_factor = Eigen::Vector4f::Ones();
    mat.base_color_texture = 0;
  }
  scene.materials.push_back(mat);
  return scene;
}

Camera SmallCamera() { return Camera::PinholeFromHorizontalFov(640, 480, 80.0); }

// Two cameras: cam1's pose relative to cam0 given as rig_from_cam1.
Rig TwoCameraRig(const Rigid3d& rig_from_cam1) {
  Rig rig;
  rig.cameras.push_back({"cam0", SmallCamera(), Rigid3d(), 0.0});
  rig.cameras.push_back({"cam1", SmallCamera(), rig_from_cam1.Inverse(), 0.0});
  return rig;
}

Rigid3d Yaw(double deg, const Eigen::Vector3d& centre = Eigen::Vector3d::Zero()) {
  return Rigid3d(Eigen::Quaterniond(Eigen::AngleAxisd(DegToRad(deg), Eigen::Vector3d::UnitY())), centre);
}

class Degenerate : public testing::Test {
 protected:
  void Render(const Scene& scene, const Rig& rig, const FramesFile& frames, int samples_per_pixel = 1,
              uint64_t seed = 0) {
    RenderJob job;
    job.options.samples_per_pixel = samples_per_pixel;
    job.options.seed = seed;
    job.scene = &scene;
    job.scene_name = scene.source;
    job.rig = rig;
    job.frames = frames;
    RenderDataset(job, dir_, true);
  }
  // Every pixel of every rendered view is ground, none sky: the case tests the ground.
  void ExpectOnlyGroundInView() {
    const DatasetLayout layout(dir_);
    for (const std::string cam : {"cam0", "cam1"}) {
      const ImageU8 labels = ReadLabelImage(layout.Label(cam, "000000"));
      EXPECT_EQ(std::count(labels.data.begin(), labels.data.end(), kSkyId), 0) << cam;
    }
  }
  CalibrationRun Calibrate(SemanticMode mode, const CalibrationRunOptions& options = {}) {
    return CalibrateDataset(dir_.path(), options, {mode});
  }
  const TempDir dir_;  // the rendered dataset
};

FramesFile LookingDownAt(double pitch_deg) {
  // Rig 1.6 m above the ground plane, pitched down so the plane fills the views.
  FramesFile f = MakeStraightTrajectory(Eigen::Vector3d(0, 1.6, 0), 0.0, 2, 1.0);
  for (Frame& frame : f.frames) {
    const Rigid3d pitch(Eigen::Quaterniond(Eigen::AngleAxisd(DegToRad(pitch_deg), Eigen::Vector3d::UnitX())),
                        Eigen::Vector3d::Zero());
    frame.rig_from_world = pitch * *frame.rig_from_world;
  }
  return f;
}

// LookingDownAt(50): the camera's x axis points right and y down, so +50 deg about x turns the
// view down; with the 64 deg vertical field of view the ground fills every image, no horizon.
TEST_F(Degenerate, FeaturelessImagesAreDiagnosed) {
  // An untextured ground plane, evenly lit: nothing to detect.
  Render(GroundPlane(200, false), TwoCameraRig(Yaw(20, Eigen::Vector3d(0.5, 0, 0))), LookingDownAt(50));
  ExpectOnlyGroundInView();
  const CalibrationRun run = Calibrate(SemanticMode::kNone);
  const RigCalibrationResult& r = run.results.at(0);
  ASSERT_EQ(r.pairwise.pairs.size(), 1u);
  EXPECT_FALSE(r.pairwise.pairs[0].two_view.success);
  EXPECT_THAT(r.pairwise.pairs[0].Outcome(), testing::AnyOf(PairOutcome::kScreenedOut, PairOutcome::kTwoViewFailed))
      << r.pairwise.pairs[0].two_view.failure_reason;
  EXPECT_FALSE(r.rig.cameras[1].cam_from_rig.has_value());
  EXPECT_EQ(r.camera_status[1].outcome, CameraOutcome::kNotConnected) << r.camera_status[1];
}

TEST_F(Degenerate, EverythingMaskedAwayIsDiagnosed) {
  // A textured ground that calibrates without semantics, with a mask that keeps no class of it.
  Render(GroundPlane(40, true), TwoCameraRig(Yaw(20, Eigen::Vector3d(0.5, 0, 0))), LookingDownAt(50));
  ExpectOnlyGroundInView();
  CalibrationRunOptions options;
  options.reliable = ReliableClasses::FromNames({"rail track"});  // not in the scene
  const std::vector<RigCalibrationResult> both =
      CalibrateDataset(dir_.path(), options, {SemanticMode::kNone, SemanticMode::kMask}).results;
  EXPECT_GT(both[0].pairwise.mean_keypoints_per_image, 100.0);
  EXPECT_TRUE(both[0].pairwise.pairs[0].two_view.success) << both[0].pairwise.pairs[0].two_view.failure_reason;
  const RigCalibrationResult& r = both[1];
  EXPECT_EQ(r.pairwise.mean_keypoints_per_image, 0.0);
  EXPECT_FALSE(r.pairwise.pairs[0].two_view.success);
  EXPECT_FALSE(r.pairwise.pairs[0].two_view.failure_reason.empty());
  EXPECT_EQ(r.camera_status[1].outcome, CameraOutcome::kNotConnected) << r.camera_status[1];
}

TEST_F(Degenerate, ViewsThatShareNothingAreNotConnected) {
  // Back to back on the street: nothing in common.
  const Scene street = LoadGltf("assets/scenes/street.glb");
  Render(street, TwoCameraRig(Yaw(180, Eigen::Vector3d(0, 0, -0.3))),
         MakeStraightTrajectory(Eigen::Vector3d(0, 1.6, 4), 0.0, 1, 1.0));
  const CalibrationRun run = Calibrate(SemanticMode::kNone);
  const RigCalibrationResult& r = run.results.at(0);
  EXPECT_FALSE(r.pairwise.pairs[0].two_view.success) << "a pose between views that share nothing";
  EXPECT_FALSE(r.rig.cameras[1].cam_from_rig.has_value());
  EXPECT_EQ(r.camera_status[1].outcome, CameraOutcome::kNotConnected) << r.camera_status[1];
}

TEST_F(Degenerate, PureRotationGivesTheRotationAndNoPosition) {
  const Scene street = LoadGltf("assets/scenes/street.glb");
  Render(street, TwoCameraRig(Yaw(35)), MakeStraightTrajectory(Eigen::Vector3d(0, 1.6, 4), 0.0, 1, 1.0));
  const CalibrationRun run = Calibrate(SemanticMode::kNone);
  const RigCalibrationResult& r = run.results.at(0);
  const PairResult& p = r.pairwise.pairs[0];
  const PairAgainstTruth& truth = run.Truth(0)->pairs.at(0);
  ASSERT_TRUE(p.two_view.success) << p.two_view.failure_reason;
  EXPECT_TRUE(p.two_view.rotation_only);
  ASSERT_TRUE(truth.rotation_error_deg.has_value());
  EXPECT_LT(*truth.rotation_error_deg, 0.1);
  EXPECT_FALSE(truth.translation_direction_error_deg.has_value());
  // The rig has no position for cam1, only its rotation.
  EXPECT_FALSE(r.rig.cameras[1].cam_from_rig.has_value());
  EXPECT_EQ(r.camera_status[1].outcome, CameraOutcome::kRotationOnly) << r.camera_status[1];
}

TEST_F(Degenerate, PlanarSceneIsSolvedOrDiagnosedNeverWrong) {
  // Down (+50 deg) at a 20 m plane: looking up at the sky, or on a 200 m plane (a texel of 20 cm, a
  // blur at 2-5 m), this case had (next to) no features and passed through its "diagnosed" branch.
  Render(GroundPlane(20, true), TwoCameraRig(Yaw(20, Eigen::Vector3d(0.5, 0, 0))), LookingDownAt(50));
  const CalibrationRun run = Calibrate(SemanticMode::kNone);
  const RigCalibrationResult& r = run.results.at(0);
  const PairResult& p = r.pairwise.pairs[0];
  const PairAgainstTruth& truth = run.Truth(0)->pairs.at(0);
  // The textured ground does give a pose (measured: 0.013 deg, 0.09 deg): the branch that checks
  // it must not be skipped unnoticed again.
  EXPECT_TRUE(p.two_view.success && !p.two_view.rotation_only) << p.two_view.failure_reason;
  if (p.two_view.success && !p.two_view.rotation_only) {
    ASSERT_TRUE(truth.rotation_error_deg && truth.translation_direction_error_deg);
    EXPECT_LT(*truth.rotation_error_deg, 0.1);
    EXPECT_LT(*truth.translation_direction_error_deg, 2.0);
    // Solved, and said to rest on a plane: the homography explains the matches as well.
    EXPECT_EQ(p.two_view.pair_type, PairType::kPlanar) << p.two_view.num_homography_inliers << " homography vs " << p.two_view.num_inliers
                                              << " essential inliers";
  } else {
    EXPECT_FALSE(p.two_view.failure_reason.empty() && !p.two_view.rotation_only);
  }
}

TEST_F(Degenerate, WeakRigMotionGivesRotationsNotWrongPositions) {
  // The demo ring at 640x360, driven 3 frames straight ahead: few features, and a motion without a
  // turn, which barely links the cameras' positions. Each render seed lands elsewhere on that edge;
  // a weaker observability test (eigenvalue ratio >= 20, the smallest clamped at 0) reports every
  // camera "calibrated" with a wrong position:
  //   seed 2: ratio 26.4, positions 29-89 deg wrong;
  //   seed 6: smallest eigenvalue -0.009 (clamped: ratio infinite), positions 57-117 deg wrong.
  const Scene street = LoadGltf("assets/scenes/street.glb");
  RingRigOptions ring;
  ring.width = 640;
  ring.height = 360;
  const Rig rig = MakeRingRig(ring);
  for (const uint64_t seed : {2, 6}) {
    SCOPED_TRACE("render seed " + std::to_string(seed));
    fs::remove_all(dir_);
    Render(street, rig, MakeStraightTrajectory(Eigen::Vector3d(0, 1.6, 4), 0.0, 3, 2.0), 4, seed);
    const CalibrationRun run = Calibrate(SemanticMode::kNone);
    const RigCalibrationResult& r = run.results.at(0);
    ASSERT_NE(run.Truth(0), nullptr);
    for (size_t c = 1; c < rig.cameras.size(); ++c) {
      const CameraAgainstTruth& s = run.Truth(0)->cameras[c];
      ASSERT_TRUE(s.rotation_error_deg.has_value()) << r.camera_status[c];
      EXPECT_LT(*s.rotation_error_deg, 1.0) << rig.cameras[c].name;
      if (r.rig.cameras[c].cam_from_rig.has_value()) {  // a position was given: it must be right
        ASSERT_TRUE(s.translation_direction_error_deg.has_value());
        EXPECT_LT(*s.translation_direction_error_deg, 5.0) << rig.cameras[c].name << ": " << r.camera_status[c];
      } else {
        EXPECT_EQ(r.camera_status[c].outcome, CameraOutcome::kRotationOnly) << r.camera_status[c];
      }
    }
  }
}

}  // namespace
}  // namespace rigsim
