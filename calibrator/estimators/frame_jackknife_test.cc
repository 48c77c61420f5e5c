#include "calibrator/estimators/frame_jackknife.h"

#include <cmath>
#include <cstdio>
#include <random>

#include <gtest/gtest.h>
#include <Eigen/Eigenvalues>

#include "calibrator/estimators/bundle_covariance.h"
#include "geometry/rigid3.h"
#include "testing/synthetic_rig.h"

namespace rigsim {
namespace {

// Two pinhole cameras 1 m apart, the second turned 20 deg, on a rig that moves 0.5 m and turns
// 3 deg per frame through a field of points 4-12 m away; every point is seen by every view it
// falls in.
struct TwoCameraDrive {
  std::vector<Camera> cameras;
  RigPoses truth;
  std::vector<Eigen::Vector3d> points;
  std::vector<ViewTrack> tracks;
};

TwoCameraDrive MakeDrive(int frames, std::mt19937& rng) {
  TwoCameraDrive d;
  const Camera cam(CameraModelId::kPinhole, 640, 480, {400, 400, 319.5, 239.5});
  d.cameras = {cam, cam};
  const Eigen::Matrix3d r1 = Eigen::AngleAxisd(20.0 * M_PI / 180, Eigen::Vector3d::UnitY()).toRotationMatrix();
  d.truth.cam_from_rig = {Rigid3d(), Rigid3d(r1, -(r1 * Eigen::Vector3d(1.0, 0.0, 0.1)))};
  for (int k = 0; k < frames; ++k) {
    const Eigen::Matrix3d turn = Eigen::AngleAxisd(3.0 * k * M_PI / 180, Eigen::Vector3d::UnitY()).toRotationMatrix();
    d.truth.rig_from_world.push_back(Rigid3d(turn, -(turn * Eigen::Vector3d(0.5 * k, 0.0, 0.0))));
  }
  std::uniform_real_distribution<double> x(-4.0, 7.0), y(-2.0, 2.0), z(4.0, 12.0);
  while (d.points.size() < 400) {
    const Eigen::Vector3d p(x(rng), y(rng), z(rng));
    ViewTrack t;
    for (int k = 0; k < frames; ++k) {
      for (int c = 0; c < 2; ++c) {
        const Eigen::Vector3d in_cam = d.truth.CamFromWorld(c, k) * p;
        const auto px = cam.ImgFromCam(in_cam);
        if (in_cam.z() > 0 && px && cam.IsInImage(*px)) t.observations.push_back({c, k, static_cast<int>(d.points.size())});
      }
    }
    if (t.observations.size() < 3) continue;
    d.tracks.push_back(t);
    d.points.push_back(p);
  }
  return d;
}

// Every point's projection in every view (keypoint index = point index; unseen ones are never
// referenced), with `noise_px` per coordinate; in `jolted_frame` camera 1 sees from
// `jolt * cam_from_rig` instead of its place in the rig (a mount that gives for a moment).
FrameKeypoints Observe(const TwoCameraDrive& d, double noise_px, std::mt19937& rng, int jolted_frame = -1,
                       const Rigid3d& jolt = Rigid3d()) {
  std::normal_distribution<double> noise(0.0, noise_px);
  const int frames = static_cast<int>(d.truth.rig_from_world.size());
  FrameKeypoints kp(frames, std::vector<std::vector<Eigen::Vector2d>>(2));
  for (int k = 0; k < frames; ++k) {
    for (int c = 0; c < 2; ++c) {
      const Rigid3d cam_from_world =
          (k == jolted_frame && c == 1 ? jolt : Rigid3d()) * d.truth.CamFromWorld(c, k);
      for (const Eigen::Vector3d& p : d.points) {
        const Eigen::Vector2d px = d.cameras[c].ImgFromCam(cam_from_world * p).value_or(Eigen::Vector2d::Zero());
        kp[k][c].push_back(px + Eigen::Vector2d(noise(rng), noise(rng)));
      }
    }
  }
  return kp;
}

struct Solved {
  MultiFrameBundleAdjustmentResult ba;
  FrameJackknife jackknife;
};

Solved SolveAndJackknife(const TwoCameraDrive& d, const FrameKeypoints& kp) {
  Solved s;
  const RigBundleAdjustmentOptions options;
  s.ba = MultiFrameRigBundleAdjust(d.cameras, kp, d.tracks, d.truth, 1, options);
  s.jackknife = JackknifeOverFrames(SolvedProblem(d.cameras, kp, d.tracks, 1, options, false, nullptr, s.ba));
  return s;
}

TEST(FrameJackknife, IsZeroOnExactObservations) {
  std::mt19937 rng(TestSeed());
  const TwoCameraDrive d = MakeDrive(4, rng);
  const Solved s = SolveAndJackknife(d, Observe(d, 0.0, rng));
  EXPECT_EQ(s.jackknife.groups_left_out, 4);
  EXPECT_FALSE(s.jackknife.rotation_std_deg[0].has_value());
  ASSERT_TRUE(s.jackknife.rotation_std_deg[1] && s.jackknife.direction_std_deg[1]);
  EXPECT_LT(*s.jackknife.rotation_std_deg[1], 1e-6);
  EXPECT_LT(*s.jackknife.direction_std_deg[1], 1e-6);
}

TEST(FrameJackknife, NeedsThreePosedFrames) {
  std::mt19937 rng(TestSeed());
  const TwoCameraDrive d = MakeDrive(2, rng);
  const Solved s = SolveAndJackknife(d, Observe(d, 0.3, rng));
  EXPECT_EQ(s.jackknife.groups_left_out, 0);
  EXPECT_FALSE(s.jackknife.rotation_std_deg[1].has_value());
}

// In one frame camera 1 sits 3 cm to the side, turned to see the scene's middle depth where it
// did (a mount that gives for a moment). Left out, that frame moves the camera by its share of the
// error, so the jackknife states about the error. The jolted frame is frame 0, whose leaving out
// hands the gauge to frame 1.
TEST(FrameJackknife, StatesTheErrorAJoltedFrameBrings) {
  std::mt19937 rng(TestSeed());
  const TwoCameraDrive d = MakeDrive(4, rng);
  const Rigid3d jolt(Eigen::AngleAxisd(-0.03 / 8.0, Eigen::Vector3d::UnitY()).toRotationMatrix(),
                     Eigen::Vector3d(-0.03, 0.0, 0.0));
  const Solved s = SolveAndJackknife(d, Observe(d, 0.2, rng, 0, jolt));
  ASSERT_TRUE(s.ba.centre_covariance[1] && s.jackknife.direction_std_deg[1]);
  const Eigen::Vector3d centre = s.ba.poses.cam_from_rig[1]->SourceOriginInTarget();
  const double error = AngleBetweenDeg(centre, d.truth.cam_from_rig[1]->SourceOriginInTarget());
  const double covariance = DirectionStdDeg(centre, *s.ba.centre_covariance[1]);
  std::printf("direction error %.4f deg, covariance %.4f deg, jackknife %.4f deg, RMS %.3f px\n", error, covariance,
              *s.jackknife.direction_std_deg[1], s.ba.reprojection_rms_px);
  EXPECT_GT(*s.jackknife.direction_std_deg[1], 0.5 * error);
  EXPECT_LT(*s.jackknife.direction_std_deg[1], 2.0 * error);
}

// Beyond ten posed frames, runs of consecutive frames leave together: ten adjustments, and a jolt
// in frame 0 (left out with frame 1, the gauge going to frame 2) is still stated.
TEST(FrameJackknife, LeavesOutRunsOfFramesBeyondTen) {
  std::mt19937 rng(TestSeed());
  const TwoCameraDrive d = MakeDrive(13, rng);
  const Rigid3d jolt(Eigen::AngleAxisd(-0.03 / 8.0, Eigen::Vector3d::UnitY()).toRotationMatrix(),
                     Eigen::Vector3d(-0.03, 0.0, 0.0));
  const Solved s = SolveAndJackknife(d, Observe(d, 0.2, rng, 0, jolt));
  EXPECT_EQ(s.jackknife.groups_left_out, 10);
  ASSERT_TRUE(s.jackknife.direction_std_deg[1]);
  const double error = AngleBetweenDeg(s.ba.poses.cam_from_rig[1]->SourceOriginInTarget(),
                                       d.truth.cam_from_rig[1]->SourceOriginInTarget());
  std::printf("direction error %.4f deg, jackknife %.4f deg\n", error, *s.jackknife.direction_std_deg[1]);
  EXPECT_GT(*s.jackknife.direction_std_deg[1], 0.5 * error);
  EXPECT_LT(*s.jackknife.direction_std_deg[1], 2.0 * error);
}

// On independent keypoint errors the jackknife states the estimate's spread over noise draws, as
// the covariance does.
TEST(FrameJackknife, StatesTheSpreadOfIndependentErrors) {
  std::mt19937 rng(TestSeed());
  const TwoCameraDrive d = MakeDrive(6, rng);
  constexpr int kDraws = 24;
  Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
  double stated = 0.0;
  for (int i = 0; i < kDraws; ++i) {
    const Solved s = SolveAndJackknife(d, Observe(d, 0.5, rng));
    ASSERT_TRUE(s.jackknife.rotation_std_deg[1]);
    const Eigen::AngleAxisd e(s.ba.poses.cam_from_rig[1]->rotation * d.truth.cam_from_rig[1]->rotation.inverse());
    const Eigen::Vector3d v = RadToDeg(e.angle()) * e.axis();
    scatter += v * v.transpose() / kDraws;
    stated += *s.jackknife.rotation_std_deg[1] / kDraws;
  }
  const double spread = std::sqrt(Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(scatter).eigenvalues().maxCoeff());
  std::printf("rotation spread %.4f deg, jackknife %.4f deg\n", spread, stated);
  EXPECT_GT(stated, 0.6 * spread);
  EXPECT_LT(stated, 1.7 * spread);
}

}  // namespace
}  // namespace rigsim
