#include "calibrator/stages/rig_adjustment_cache.h"

#include <cmath>
#include <cstring>
#include <random>

#include <gtest/gtest.h>

#include "testing/synthetic_rig.h"

namespace rigsim {
namespace {

// Two pinhole cameras 0.4 m apart, turned 20 deg, seeing 200 points 4-12 m away in one frame,
// with 0.5 px of noise; the start is the truth with camera 1 a little off.
struct TwoCameraProblem {
  std::vector<Camera> cameras;
  FrameKeypoints keypoints;
  std::vector<ViewTrack> tracks;
  RigPoses start;
  RigBundleAdjustmentOptions options;

  StartAdjustmentInputs Inputs() const {
    return {.cameras = cameras, .keypoints = keypoints, .tracks = tracks, .start = start, .scale_camera = 1,
            .options = options};
  }
};

TwoCameraProblem MakeProblem() {
  std::mt19937 rng(TestSeed());
  TwoCameraProblem p;
  const Camera cam(CameraModelId::kPinhole, 640, 480, {400, 400, 319.5, 239.5});
  p.cameras = {cam, cam};
  const Eigen::Matrix3d r1 = Eigen::AngleAxisd(20.0 * M_PI / 180, Eigen::Vector3d::UnitY()).toRotationMatrix();
  const Eigen::Vector3d c1(0.4, 0.0, 0.05);
  const Rigid3d cam1_from_rig(r1, -(r1 * c1));
  p.keypoints.assign(1, std::vector<std::vector<Eigen::Vector2d>>(2));
  std::uniform_real_distribution<double> u(-1.0, 1.0), depth(4.0, 12.0);
  std::normal_distribution<double> noise(0.0, 0.5);
  while (p.tracks.size() < 200) {
    const double z = depth(rng);
    const Eigen::Vector3d x(u(rng) * 0.6 * z, u(rng) * 0.5 * z, z);
    const auto p0 = cam.ImgFromCam(x), p1 = cam.ImgFromCam(cam1_from_rig * x);
    if (!p0 || !p1 || !cam.IsInImage(*p0) || !cam.IsInImage(*p1)) continue;
    const int k = static_cast<int>(p.tracks.size());
    p.keypoints[0][0].push_back(*p0 + Eigen::Vector2d(noise(rng), noise(rng)));
    p.keypoints[0][1].push_back(*p1 + Eigen::Vector2d(noise(rng), noise(rng)));
    p.tracks.push_back({{{0, 0, k}, {1, 0, k}}});
  }
  const Eigen::Matrix3d off = Eigen::AngleAxisd(0.02, Eigen::Vector3d::UnitX()).toRotationMatrix();
  p.start.cam_from_rig = {Rigid3d(), Rigid3d(off * r1, -(r1 * Eigen::Vector3d(0.38, 0.02, 0.06)))};
  p.start.rig_from_world = {Rigid3d()};
  return p;
}

// The same bits: a reused adjustment must be exactly the solve it stands for.
void ExpectSameBits(const AdjustedStart& a, const AdjustedStart& b) {
  EXPECT_EQ(std::memcmp(&a.cost, &b.cost, sizeof a.cost), 0);
  EXPECT_EQ(a.cost_observations, b.cost_observations);
  EXPECT_EQ(a.ba.iterations, b.ba.iterations);
  EXPECT_EQ(a.ba.num_observations, b.ba.num_observations);
  EXPECT_EQ(std::memcmp(&a.ba.reprojection_rms_px, &b.ba.reprojection_rms_px, sizeof(double)), 0);
  ASSERT_TRUE(a.ba.poses.cam_from_rig[1] && b.ba.poses.cam_from_rig[1]);
  const Rigid3d& pa = *a.ba.poses.cam_from_rig[1];
  const Rigid3d& pb = *b.ba.poses.cam_from_rig[1];
  EXPECT_EQ(std::memcmp(pa.rotation.coeffs().data(), pb.rotation.coeffs().data(), 4 * sizeof(double)), 0);
  EXPECT_EQ(std::memcmp(pa.translation.data(), pb.translation.data(), 3 * sizeof(double)), 0);
}

TEST(RigAdjustmentCache, IdenticalInputsAreSolvedOnceAndGiveTheSameBits) {
  const TwoCameraProblem p = MakeProblem();
  RigAdjustmentCache cache;
  const AdjustedStart first = cache.Adjust(p.Inputs());
  EXPECT_FALSE(first.reused);
  EXPECT_GT(first.ba.iterations, 0);
  // Copies of the inputs, as a later round makes them: equal, not the same objects.
  const TwoCameraProblem copy = p;
  const AdjustedStart again = cache.Adjust(copy.Inputs());
  EXPECT_TRUE(again.reused);
  ExpectSameBits(again, first);
  ExpectSameBits(again, AdjustStart(p.Inputs()));
}

TEST(RigAdjustmentCache, AnyInputThatDiffersIsSolvedAgain) {
  const TwoCameraProblem p = MakeProblem();
  RigAdjustmentCache cache;
  ASSERT_FALSE(cache.Adjust(p.Inputs()).reused);
  auto expect_solved = [&](const TwoCameraProblem& changed, const char* what) {
    const AdjustedStart a = cache.Adjust(changed.Inputs());
    EXPECT_FALSE(a.reused) << what;
    ExpectSameBits(a, AdjustStart(changed.Inputs()));
  };
  TwoCameraProblem q = p;
  q.start.cam_from_rig[1]->translation.x() = std::nextafter(q.start.cam_from_rig[1]->translation.x(), 1.0);
  expect_solved(q, "a start one bit apart");
  q = p;
  q.keypoints[0][1][7].y() += 1e-9;
  expect_solved(q, "a keypoint a track observes");
  q = p;
  q.tracks.pop_back();
  expect_solved(q, "a track fewer");
  q = p;
  q.options.max_iterations = 99;
  expect_solved(q, "other options");
  q = p;
  q.options.intrinsics_priors.focal_fraction = 0.04;
  expect_solved(q, "other intrinsics priors");
  q = p;
  q.cameras[1] = Camera(CameraModelId::kPinhole, 640, 480, {401, 400, 319.5, 239.5});
  expect_solved(q, "other intrinsics");
  // A keypoint no track observes is not read by the solve: the adjustment is the one kept.
  q = p;
  q.keypoints[0][1].push_back(Eigen::Vector2d(1, 2));
  EXPECT_TRUE(cache.Adjust(q.Inputs()).reused);
}

}  // namespace
}  // namespace rigsim
