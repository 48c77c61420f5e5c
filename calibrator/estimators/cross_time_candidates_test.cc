#include "calibrator/estimators/cross_time_candidates.h"

#include <set>

#include <gtest/gtest.h>

#include "geometry/rigid3.h"
#include "testing/synthetic_rig.h"

namespace rigsim {
namespace {

// A ring of four 90-deg cameras looking out every 90 deg (so that neighbours share nothing at one
// instant) on a path turning 15 deg a frame.
struct Ring {
  std::vector<Camera> cameras;
  std::vector<Eigen::Quaterniond> q;  // cam_from_rig
  std::vector<Rigid3d> path;          // rig_from_world per frame

  Ring() {
    for (int c = 0; c < 4; ++c) {
      cameras.push_back(Camera::PinholeFromHorizontalFov(640, 360, 90.0));
      q.push_back(Eigen::Quaterniond(Eigen::AngleAxisd(DegToRad(-90.0 * c), Eigen::Vector3d::UnitY())));
    }
    path = TurningPath(16, 1.0, 15.0, 0.0, 0.0, 0.0);
  }
  CrossTimeCandidateInputs Inputs(bool rotations_known) const {
    CrossTimeCandidateInputs in;
    in.cameras = cameras;
    for (int c = 0; c < 4; ++c) in.cam_from_rig.push_back(rotations_known || c == 0 ? std::optional(q[c]) : std::nullopt);
    for (const Rigid3d& p : path) in.rig_from_world.push_back(p.rotation);
    return in;
  }
  // The angle between the optical axes of two views in the world.
  double AxisAngleDeg(int a, int t, int b, int u) const {
    const Eigen::Vector3d za = ((q[a] * path[t].rotation).conjugate() * Eigen::Vector3d::UnitZ());
    const Eigen::Vector3d zb = ((q[b] * path[u].rotation).conjugate() * Eigen::Vector3d::UnitZ());
    return AngleBetweenDeg(za, zb);
  }
};

TEST(CrossTimeCandidates, PredictedPairsLookTheSameWay) {
  const Ring ring;
  const CrossTimeCandidateOptions options;
  const std::vector<CrossTimeCandidate> cs = SelectCrossTimeCandidates(ring.Inputs(true), options);
  std::set<std::pair<int, int>> camera_pairs;
  for (const CrossTimeCandidate& c : cs) {
    ASSERT_TRUE(c.predicted_overlap);
    EXPECT_GE(*c.predicted_overlap, options.min_predicted_overlap);
    EXPECT_NE(c.frame_a, c.frame_b);
    // Overlap at infinity means the axes are closer than a field of view.
    EXPECT_LT(ring.AxisAngleDeg(c.cam_a, c.frame_a, c.cam_b, c.frame_b), 90.0);
    camera_pairs.insert({c.cam_a, c.cam_b});
  }
  // Over 16 frames (225 deg) every two cameras meet, and every camera meets itself again.
  for (int a = 0; a < 4; ++a) {
    for (int b = a; b < 4; ++b) EXPECT_TRUE(camera_pairs.count({a, b})) << a << "-" << b;
  }
  // At most max_per_camera_pair each.
  for (const auto& p : camera_pairs) {
    const long count = std::count_if(cs.begin(), cs.end(), [&](const CrossTimeCandidate& c) {
      return c.cam_a == p.first && c.cam_b == p.second;
    });
    EXPECT_LE(count, options.max_per_camera_pair);
  }
  // The best of a pair of two cameras looks almost the same way.
  const auto first = std::find_if(cs.begin(), cs.end(), [](const CrossTimeCandidate& c) { return c.cam_a != c.cam_b; });
  ASSERT_NE(first, cs.end());
  EXPECT_LT(ring.AxisAngleDeg(first->cam_a, first->frame_a, first->cam_b, first->frame_b), 15.0);
}

TEST(CrossTimeCandidates, ViewsFarApartForTheSceneDepthDoNotOverlap) {
  const Ring ring;
  CrossTimeCandidateInputs in = ring.Inputs(true);
  for (const Rigid3d& p : ring.path) in.rig_centre_in_world.push_back(p.SourceOriginInTarget());
  in.scene_depth = 1e6;  // far: as at infinity
  EXPECT_EQ(PredictedViewOverlap(in, 0, 0, 0, 3), PredictedViewOverlap(ring.Inputs(true), 0, 0, 0, 3));
  in.scene_depth = 0.05;  // a scene much nearer than the path's steps: nothing seen twice
  EXPECT_EQ(*PredictedViewOverlap(in, 0, 0, 0, 3), 0.0);
  EXPECT_FALSE(PredictedViewOverlap(ring.Inputs(false), 0, 0, 1, 3));
}

TEST(CrossTimeCandidates, CamerasWithoutARotationAreSearchedByTheRigsTurn) {
  const Ring ring;
  CrossTimeCandidateOptions options;
  const std::vector<CrossTimeCandidate> cs = SelectCrossTimeCandidates(ring.Inputs(false), options);
  std::vector<Eigen::Quaterniond> turns;  // of the rig, over camera 0 and 1's search pairs
  for (const CrossTimeCandidate& c : cs) {
    if (c.predicted_overlap) {  // only camera 0 with itself has a rotation
      EXPECT_EQ(c.cam_a, 0);
      EXPECT_EQ(c.cam_b, 0);
      continue;
    }
    EXPECT_NE(c.cam_a, c.cam_b);
    if (c.cam_a == 0 && c.cam_b == 1) {
      turns.push_back(ring.path[c.frame_b].rotation * ring.path[c.frame_a].rotation.conjugate());
    }
  }
  // Every turn the path makes between two frames (multiples of 15 deg, all the way round; no turn
  // is the same instant, not a cross-time pair) is searched, each about once.
  for (int k = -11; k <= 12; ++k) {
    if (k == 0) continue;
    const Eigen::Quaterniond turn(Eigen::AngleAxisd(DegToRad(15.0 * k), Eigen::Vector3d::UnitY()));
    const long near = std::count_if(turns.begin(), turns.end(),
                                    [&](const Eigen::Quaterniond& t) { return RotationDifferenceDeg(t, turn) < 1.0; });
    EXPECT_GE(near, 1) << 15 * k << " deg";
    EXPECT_LE(near, 2) << 15 * k << " deg";
  }
  options.max_search_per_camera_pair = 5;
  const auto capped = SelectCrossTimeCandidates(ring.Inputs(false), options);
  EXPECT_EQ(std::count_if(capped.begin(), capped.end(), [](const auto& c) { return !c.predicted_overlap; }), 6 * 5);
}

TEST(CrossTimeCandidates, BadInputThrows) {
  const Ring ring;
  CrossTimeCandidateInputs in = ring.Inputs(true);
  in.cam_from_rig.pop_back();
  EXPECT_THROW(SelectCrossTimeCandidates(in, {}), std::invalid_argument);
  CrossTimeCandidateOptions bad;
  bad.min_frame_gap = 1;
  EXPECT_THROW(SelectCrossTimeCandidates(ring.Inputs(true), bad), std::invalid_argument);
}

}  // namespace
}  // namespace rigsim
