#include "calibrator/estimators/rig_rotation_averaging.h"

#include <random>

#include <gtest/gtest.h>

#include "geometry/rigid3.h"
#include "testing/synthetic_rig.h"

namespace rigsim {
namespace {

// The truth: cameras' rotations in the rig (camera 0 the identity) and the rig's per frame (frame 0
// the identity), and measurements made from it.
struct Truth {
  std::vector<Eigen::Quaterniond> q, r;

  Truth(int cameras, const std::vector<Rigid3d>& path, std::mt19937& rng) {
    for (const Rigid3d& p : RandomCamFromRig(cameras, rng)) q.push_back(p.rotation);
    for (const Rigid3d& p : path) r.push_back(p.rotation);
  }
  ViewPairRotation Pair(int a, int t, int b, int u, int inliers = 100) const {
    return {a, b, t, u, q[b] * r[u] * r[t].conjugate() * q[a].conjugate(), inliers};
  }
  ViewPairRotation Pooled(int a, int b, int inliers = 100) const {
    return {a, b, -1, -1, q[b] * q[a].conjugate(), inliers};
  }
  // Every camera's own motion between consecutive frames.
  void AddMotion(int camera, std::vector<ViewPairRotation>* ms) const {
    for (int k = 0; k + 1 < static_cast<int>(r.size()); ++k) ms->push_back(Pair(camera, k, camera, k + 1));
  }
};

void ExpectExact(const RigRotationAveragingResult& res, const Truth& t, double tol_deg) {
  for (size_t c = 0; c < t.q.size(); ++c) {
    ASSERT_TRUE(res.cam_from_rig[c]) << "camera " << c;
    EXPECT_LT(RotationDifferenceDeg(*res.cam_from_rig[c], t.q[c]), tol_deg) << "camera " << c;
  }
  for (size_t k = 0; k < t.r.size(); ++k) {
    ASSERT_TRUE(res.rig_from_world[k]) << "frame " << k;
    EXPECT_LT(RotationDifferenceDeg(*res.rig_from_world[k], t.r[k]), tol_deg) << "frame " << k;
  }
}

// A ring whose cameras never see the same thing at one instant: only cross-time pairs link them.
TEST(RigRotationAveraging, CrossTimePairsLinkCamerasWithoutOverlap) {
  std::mt19937 rng = TestRng();
  const Truth t(4, TurningPath(8, 2.0, 12.0, 0.0, 0.0, 0.0), rng);
  std::vector<ViewPairRotation> ms;
  for (int c = 0; c < 4; ++c) t.AddMotion(c, &ms);
  ms.push_back(t.Pair(0, 1, 1, 6));
  ms.push_back(t.Pair(1, 0, 2, 5));
  ms.push_back(t.Pair(3, 6, 2, 2));
  const RigRotationAveragingResult res = AverageRigRotations(4, 8, ms, {}, {});
  ExpectExact(res, t, 1e-6);
  EXPECT_EQ(res.num_outliers, 0);
}

// Without cross-time pairs, a camera's own motion fixes it only together with a start: over turns
// about two axes it is refined from a start 3 deg off to the truth (hand-eye calibration inside the
// averaging).
TEST(RigRotationAveraging, OwnMotionRefinesAStartOverGeneralTurns) {
  std::mt19937 rng = TestRng();
  const Truth t(3, TurningPath(8, 2.0, 10.0, 0.3, 6.0, 4.0), rng);
  std::vector<ViewPairRotation> ms;
  for (int c = 0; c < 3; ++c) t.AddMotion(c, &ms);
  std::vector<std::optional<Eigen::Quaterniond>> starts(3);
  starts[1] = RandomRotationBy(rng, 3.0) * t.q[1];
  starts[2] = RandomRotationBy(rng, 3.0) * t.q[2];
  const RigRotationAveragingResult res = AverageRigRotations(3, 8, ms, starts, {});
  ExpectExact(res, t, 1e-6);
}

TEST(RigRotationAveraging, ACameraNothingReachesHasNoRotation) {
  std::mt19937 rng = TestRng();
  const Truth t(3, TurningPath(5, 2.0, 10.0, 0.3, 0.0, 0.0), rng);
  std::vector<ViewPairRotation> ms;
  for (int c = 0; c < 3; ++c) t.AddMotion(c, &ms);
  ms.push_back(t.Pooled(0, 1));
  const RigRotationAveragingResult res = AverageRigRotations(3, 5, ms, {}, {});
  EXPECT_TRUE(res.cam_from_rig[1]);
  EXPECT_FALSE(res.cam_from_rig[2]);
  for (int k = 0; k < 5; ++k) EXPECT_TRUE(res.rig_from_world[k]) << k;
}

// Camera 0 lost between frames 2 and 3: camera 1, placed by a pooled pair, carries the rig across.
TEST(RigRotationAveraging, AnotherCameraBridgesABreakInTheReferencesMotion) {
  std::mt19937 rng = TestRng();
  const Truth t(2, TurningPath(6, 2.0, 10.0, 0.3, 0.0, 0.0), rng);
  std::vector<ViewPairRotation> ms;
  t.AddMotion(0, &ms);
  ms.erase(ms.begin() + 2);  // frame 2 -> 3 of camera 0
  t.AddMotion(1, &ms);
  ms.push_back(t.Pooled(0, 1));
  ExpectExact(AverageRigRotations(2, 6, ms, {}, {}), t, 1e-6);
}

TEST(RigRotationAveraging, AWrongMeasurementIsAnOutlier) {
  std::mt19937 rng = TestRng();
  const Truth t(3, TurningPath(6, 2.0, 10.0, 0.3, 0.0, 0.0), rng);
  std::vector<ViewPairRotation> ms;
  for (int c = 0; c < 3; ++c) t.AddMotion(c, &ms);
  ms.push_back(t.Pooled(0, 1));
  ms.push_back(t.Pair(1, 0, 2, 3));
  ms.push_back(t.Pair(0, 2, 2, 4));
  ViewPairRotation wrong = t.Pair(2, 1, 1, 5, 500);  // heavy, and 30 deg off
  wrong.b_from_a = RandomRotationBy(rng, 30.0) * wrong.b_from_a;
  ms.push_back(wrong);
  const RigRotationAveragingResult res = AverageRigRotations(3, 6, ms, {}, {});
  EXPECT_TRUE(res.outlier.back());
  EXPECT_EQ(res.num_outliers, 1);
  ExpectExact(res, t, 1e-6);
}

TEST(RigRotationAveraging, BadInputThrows) {
  const ViewPairRotation out_of_range{0, 3, 0, 1, Eigen::Quaterniond::Identity(), 1};
  EXPECT_THROW(AverageRigRotations(2, 2, {out_of_range}, {}, {}), std::invalid_argument);
  const ViewPairRotation itself{1, 1, 0, 0, Eigen::Quaterniond::Identity(), 1};
  EXPECT_THROW(AverageRigRotations(2, 2, {itself}, {}, {}), std::invalid_argument);
  EXPECT_THROW(AverageRigRotations(2, 2, {}, {std::nullopt}, {}), std::invalid_argument);
}

}  // namespace
}  // namespace rigsim
