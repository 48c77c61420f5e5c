#include "calibrator/estimators/rig_resection.h"

#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "testing/synthetic_rig.h"

namespace rigsim {
namespace {

const Camera kCamera(CameraModelId::kOpenCV, 960, 600, {700, 700, 479.5, 299.5, -0.1, 0.02, 0, 0});

// A camera fixed in the rig seeing points over three frames of a moving rig: its keypoints with
// `noise_px`, each with its point in the rig frame of its frame; then `wrong` keypoints paired with
// points they are not of.
struct Scene {
  Rigid3d cam_from_rig;
  std::vector<RigResectionCorrespondence> correspondences;
  int true_ones = 0;
};

Scene MakeScene(int per_frame, int wrong, double noise_px, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1, 1);
  std::normal_distribution<double> noise(0, noise_px);
  Scene s;
  s.cam_from_rig = Rigid3d(Eigen::AngleAxisd(1.2, Eigen::Vector3d(0.1, 1, 0.05).normalized()).toRotationMatrix(),
                           Eigen::Vector3d(0.4, -0.1, 0.7));
  std::vector<Eigen::Vector3d> all_points;
  for (int f = 0; f < 3; ++f) {
    const Rigid3d rig_from_world(Eigen::AngleAxisd(0.05 * f, Eigen::Vector3d::UnitY()).toRotationMatrix(),
                                 Eigen::Vector3d(0, 0, -1.3 * f));
    const Rigid3d world_from_cam = (s.cam_from_rig * rig_from_world).Inverse();
    for (int i = 0; i < per_frame;) {
      const auto ray = kCamera.CamFromImg({480 + 470 * u(rng), 300 + 290 * u(rng)});
      if (!ray) continue;
      const Eigen::Vector3d x_world = world_from_cam * (*ray * (4 + 20 * (u(rng) + 1)));
      const Eigen::Vector3d x_in_rig = rig_from_world * x_world;
      const auto px = kCamera.ImgFromCam(s.cam_from_rig * x_in_rig);
      s.correspondences.push_back({*px + Eigen::Vector2d(noise(rng), noise(rng)), x_in_rig});
      all_points.push_back(x_in_rig);
      ++i;
    }
  }
  s.true_ones = static_cast<int>(s.correspondences.size());
  for (int i = 0; i < wrong; ++i) {
    s.correspondences.push_back({Eigen::Vector2d(480 + 470 * u(rng), 300 + 290 * u(rng)),
                                 all_points[static_cast<size_t>(i * 7919) % all_points.size()] +
                                     Eigen::Vector3d(u(rng), u(rng), u(rng)) * 3.0});
  }
  return s;
}

TEST(RigResection, PlacesACameraFromPointsOfSeveralFramesAmongManyWrongMatches) {
  const Scene s = MakeScene(10, 150, 0.5, TestSeed());
  const RigResection r = ResectCameraInRig(kCamera, s.correspondences, RigResectionOptions{});
  ASSERT_TRUE(r.success) << r.reason;
  EXPECT_LT(RotationDifferenceDeg(r.cam_from_rig.rotation, s.cam_from_rig.rotation), 0.2);
  EXPECT_LT((r.cam_from_rig.SourceOriginInTarget() - s.cam_from_rig.SourceOriginInTarget()).norm(), 0.05);
  int true_inliers = 0;
  for (int i : r.inliers) true_inliers += i < s.true_ones;
  EXPECT_GE(true_inliers, s.true_ones - 2);
  EXPECT_LE(static_cast<int>(r.inliers.size()) - true_inliers, 3);
  EXPECT_LT(r.log10_false_alarms, -10);
}

TEST(RigResection, RefusesMatchesThatNoPoseExplainsBetterThanChance) {
  Scene s = MakeScene(10, 200, 0.5, TestSeed());
  s.correspondences.erase(s.correspondences.begin(), s.correspondences.begin() + s.true_ones);
  const RigResection r = ResectCameraInRig(kCamera, s.correspondences, RigResectionOptions{});
  EXPECT_FALSE(r.success);
  EXPECT_FALSE(r.reason.empty());
  const Scene few = MakeScene(2, 0, 0.5, TestSeed());
  const RigResection too_few = ResectCameraInRig(kCamera, few.correspondences, RigResectionOptions{});
  EXPECT_FALSE(too_few.success);
  EXPECT_NE(too_few.reason.find("fewer than"), std::string::npos) << too_few.reason;
}

TEST(RigResection, FalseAlarmsFallWithInliersAndRiseWithTheInlierDisc) {
  EXPECT_LT(Log10FalseAlarms(100, 20, 1e-5), Log10FalseAlarms(100, 10, 1e-5));
  EXPECT_LT(Log10FalseAlarms(100, 10, 1e-5), Log10FalseAlarms(100, 10, 1e-3));
  // Nearly every keypoint within the disc: any pose is as likely by chance.
  EXPECT_GT(Log10FalseAlarms(100, 30, 0.9), 0.0);
  EXPECT_THROW(ResectCameraInRig(kCamera, {}, RigResectionOptions{.inlier_threshold_px = 0}), std::invalid_argument);
}

}  // namespace
}  // namespace rigsim
