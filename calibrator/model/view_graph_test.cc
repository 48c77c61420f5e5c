#include "calibrator/model/view_graph.h"

#include <gtest/gtest.h>

namespace rigsim {
namespace {

PairEstimate Pair(int a, int b, bool success, int inliers, bool rotation_only = false, std::string why = "") {
  PairEstimate p;
  p.cam_a = a;
  p.cam_b = b;
  p.two_view.success = success;
  p.two_view.num_inliers = inliers;
  p.two_view.rotation_only = rotation_only;
  p.two_view.failure_reason = std::move(why);
  p.two_view.cam_b_from_cam_a = Rigid3d(Eigen::Quaterniond(Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitY())),
                               rotation_only ? Eigen::Vector3d::Zero() : Eigen::Vector3d(2, 0, 0));
  return p;
}

TEST(ViewGraph, EdgesKeepEveryPairWithItsReason) {
  ViewGraphOptions options;
  options.min_inliers = 30;
  const ViewGraph g = BuildViewGraph(
      5, {Pair(0, 1, true, 100), Pair(1, 2, true, 10), Pair(0, 3, false, 0, false, "too few matches"), Pair(3, 4, true, 50)},
      options);
  ASSERT_EQ(g.edges.size(), 4u);
  EXPECT_TRUE(g.edges[0].active);
  EXPECT_NEAR(g.edges[0].direction.norm(), 1.0, 1e-12);  // unit direction
  EXPECT_FALSE(g.edges[1].active);
  EXPECT_NE(g.edges[1].inactive_reason.find("too few inliers (10 < 30)"), std::string::npos);
  EXPECT_EQ(g.edges[2].inactive_reason, "two-view failed: too few matches");

  const std::vector<int> comp = ConnectedComponents(g);
  EXPECT_EQ(comp, (std::vector<int>{0, 0, 2, 3, 3}));
  const std::vector<char> reached = {1, 1, 0, 0, 0};
  const std::vector<std::string> names = {"c0", "c1", "c2", "c3", "c4"};
  const std::string why2 = NotConnectedReason(g, 2, reached, names);
  EXPECT_EQ(why2, "c1-c2: too few inliers (10 < 30)");
  EXPECT_EQ(NotConnectedReason(g, 3, reached, names), "c0-c3: two-view failed: too few matches");
  EXPECT_EQ(NotConnectedReason(g, 4, reached, names), "no pair with any calibrated camera");
}

TEST(ViewGraph, ReversedPairsAreStoredLowToHigh) {
  PairEstimate p = Pair(2, 0, true, 40);
  const ViewGraph g = BuildViewGraph(3, {p}, {});
  ASSERT_EQ(g.edges.size(), 1u);
  EXPECT_EQ(g.edges[0].cam_a, 0);
  EXPECT_EQ(g.edges[0].cam_b, 2);
  const Rigid3d inv = p.two_view.cam_b_from_cam_a.Inverse();
  EXPECT_LT(RotationDifferenceDeg(g.edges[0].rotation, inv.rotation), 1e-9);
  EXPECT_LT((g.edges[0].direction - inv.translation.normalized()).norm(), 1e-12);
}

TEST(ViewGraph, RotationOnlyEdgesDoNotConnectTranslations) {
  const ViewGraph g = BuildViewGraph(3, {Pair(0, 1, true, 100), Pair(1, 2, true, 100, true)}, {});
  EXPECT_TRUE(g.edges[1].rotation_only);
  EXPECT_EQ(g.edges[1].direction, Eigen::Vector3d::Zero());
  EXPECT_EQ(ConnectedComponents(g), (std::vector<int>{0, 0, 0}));
  EXPECT_EQ(ConnectedComponents(g, /*translation_only=*/true), (std::vector<int>{0, 0, 2}));
}

TEST(ViewGraph, DeactivateKeepsTheFirstReason) {
  ViewGraph g = BuildViewGraph(2, {Pair(0, 1, true, 100)}, {});
  g.Deactivate(0, "rotation outlier");
  g.Deactivate(0, "something else");
  EXPECT_FALSE(g.edges[0].active);
  EXPECT_EQ(g.edges[0].inactive_reason, "rotation outlier");
}

TEST(ViewGraph, BadInputsThrow) {
  EXPECT_THROW(BuildViewGraph(2, {Pair(0, 2, true, 100)}, {}), std::invalid_argument);
  EXPECT_THROW(BuildViewGraph(2, {Pair(1, 1, true, 100)}, {}), std::invalid_argument);
  ViewGraphOptions bad;
  bad.min_inliers = 0;
  EXPECT_THROW(bad.Check(), std::invalid_argument);
}

}  // namespace
}  // namespace rigsim
