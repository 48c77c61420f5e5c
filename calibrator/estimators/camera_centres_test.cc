#include "calibrator/estimators/camera_centres.h"

#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "testing/synthetic_rig.h"

namespace rigsim {
namespace {

// A view graph from true rotations and centres (directions exact).
ViewGraph GraphFromTruth(const std::vector<Rigid3d>& cam_from_rig, const std::vector<std::pair<int, int>>& pairs) {
  std::vector<PairEstimate> estimates;
  for (auto [a, b] : pairs) {
    PairEstimate p;
    p.cam_a = a;
    p.cam_b = b;
    p.two_view.success = true;
    p.two_view.num_inliers = 100;
    const Rigid3d rel = cam_from_rig[b] * cam_from_rig[a].Inverse();
    p.two_view.cam_b_from_cam_a = Rigid3d(rel.rotation, rel.translation.normalized());
    estimates.push_back(p);
  }
  return BuildViewGraph(static_cast<int>(cam_from_rig.size()), estimates, {});
}

TEST(EstimateCameraCentres, ExactDirectionsGiveTheShape) {
  std::mt19937 rng = TestRng();
  const std::vector<Rigid3d> rig = RandomCamFromRig(5, rng);
  const ViewGraph graph = GraphFromTruth(rig, {{0, 1}, {0, 2}, {1, 2}, {1, 3}, {2, 3}, {3, 4}, {2, 4}});
  std::vector<std::optional<Eigen::Quaterniond>> rot;
  for (const Rigid3d& r : rig) rot.push_back(r.rotation);
  const CameraCentres c = EstimateCameraCentres(graph, rot, 0);
  EXPECT_TRUE(c.unique);
  EXPECT_EQ(c.edges_used, 7);
  ASSERT_TRUE(c.centre_in_rig[1].has_value());
  const double scale = rig[1].SourceOriginInTarget().norm() / c.centre_in_rig[1]->norm();
  for (int i = 0; i < 5; ++i) {
    EXPECT_LT((scale * *c.centre_in_rig[i] - rig[i].SourceOriginInTarget()).norm(), 1e-9) << i;
  }
}

TEST(EstimateCameraCentres, ARingOfPairsIsReportedAmbiguous) {
  // A square loop: the four edge lengths are free beyond the two closure equations.
  std::vector<Rigid3d> rig(4);
  const Eigen::Vector3d centres[4] = {{0, 0, 0}, {1, 0, 0}, {1, 0, 1}, {0, 0, 1}};
  for (int c = 0; c < 4; ++c) rig[c] = Rigid3d(Eigen::Quaterniond::Identity(), -centres[c]);
  const ViewGraph graph = GraphFromTruth(rig, {{0, 1}, {1, 2}, {2, 3}, {0, 3}});
  std::vector<std::optional<Eigen::Quaterniond>> rot(4, Eigen::Quaterniond::Identity());
  EXPECT_FALSE(EstimateCameraCentres(graph, rot, 0).unique);
  // A diagonal makes it rigid.
  const ViewGraph braced = GraphFromTruth(rig, {{0, 1}, {1, 2}, {2, 3}, {0, 3}, {0, 2}});
  EXPECT_TRUE(EstimateCameraCentres(braced, rot, 0).unique);
}

TEST(EstimateCameraCentres, CamerasWithoutRotationOrDirectionAreLeftOut) {
  std::mt19937 rng = TestRng();
  const std::vector<Rigid3d> rig = RandomCamFromRig(4, rng);
  ViewGraph graph = GraphFromTruth(rig, {{0, 1}, {1, 2}, {0, 2}, {2, 3}});
  graph.edges[3].rotation_only = true;
  graph.edges[3].direction.setZero();
  std::vector<std::optional<Eigen::Quaterniond>> rot;
  for (const Rigid3d& r : rig) rot.push_back(r.rotation);
  const CameraCentres c = EstimateCameraCentres(graph, rot, 0);
  EXPECT_TRUE(c.centre_in_rig[2].has_value());
  EXPECT_FALSE(c.centre_in_rig[3].has_value());
}

}  // namespace
}  // namespace rigsim
