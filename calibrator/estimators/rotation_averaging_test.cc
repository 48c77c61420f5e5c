#include "calibrator/estimators/rotation_averaging.h"

#include <cmath>
#include <cstdio>
#include <random>
#include <set>

#include <gtest/gtest.h>

#include "testing/synthetic_rig.h"

namespace rigsim {
namespace {

struct SyntheticGraph {
  std::vector<Eigen::Quaterniond> truth;  // cam_from_rig
  ViewGraph graph;
  std::set<int> perturbed;                // edges made outliers
};

// Complete graph over `n` cameras; inlier edges with `noise_deg` (per axis, at 200 inliers) of noise, a fraction
// `outlier_fraction` of edges rotated by 30-90 deg, and those given *more* inliers than the good
// ones, so a spanning tree by inlier count alone would pick them.
SyntheticGraph MakeGraph(std::mt19937& rng, int n, double noise_deg, double outlier_fraction) {
  SyntheticGraph s;
  for (int c = 0; c < n; ++c) s.truth.push_back(RandomRotation(rng));
  std::vector<PairEstimate> pairs;
  std::uniform_real_distribution<double> u(0, 1);
  std::normal_distribution<double> noise(0, DegToRad(noise_deg));
  for (int a = 0; a < n; ++a) {
    for (int b = a + 1; b < n; ++b) {
      PairEstimate p;
      p.cam_a = a;
      p.cam_b = b;
      p.two_view.success = true;
      p.two_view.rotation_only = true;
      Eigen::Quaterniond r = s.truth[b] * s.truth[a].conjugate();
      // Noise falls as 1/sqrt(inliers), as for a real pair (the weighting assumes it).
      p.two_view.num_inliers = 100 + static_cast<int>(200 * u(rng));
      const Eigen::Vector3d e = std::sqrt(200.0 / p.two_view.num_inliers) * Eigen::Vector3d(noise(rng), noise(rng), noise(rng));
      r = Eigen::Quaterniond(Eigen::AngleAxisd(e.norm(), e.normalized())) * r;
      if (u(rng) < outlier_fraction) {
        r = RandomRotationBy(rng, 30.0 + 60.0 * u(rng)) * r;
        s.perturbed.insert(static_cast<int>(pairs.size()));
        p.two_view.num_inliers = 400 + static_cast<int>(200 * u(rng));
      }
      p.two_view.cam_b_from_cam_a = Rigid3d(r, Eigen::Vector3d::Zero());
      pairs.push_back(p);
    }
  }
  s.graph = BuildViewGraph(n, pairs, {});
  return s;
}

// Largest (and RMS) error of the relative rotations over all camera pairs (gauge-free), degrees.
double MaxRelativeError(const RotationAveragingResult& r, const std::vector<Eigen::Quaterniond>& truth,
                        double* rms = nullptr) {
  double worst = 0.0, sum = 0.0;
  int count = 0;
  for (size_t a = 0; a < truth.size(); ++a) {
    for (size_t b = a + 1; b < truth.size(); ++b) {
      const Eigen::Quaterniond est = *r.cam_from_rig[b] * r.cam_from_rig[a]->conjugate();
      const double e = RotationDifferenceDeg(est, truth[b] * truth[a].conjugate());
      worst = std::max(worst, e);
      sum += e * e;
      ++count;
    }
  }
  if (rms) *rms = std::sqrt(sum / count);
  return worst;
}

// RMS error of the input edges that are not outliers: what averaging has to beat.
double InlierEdgeRms(const SyntheticGraph& s) {
  double sum = 0.0;
  int count = 0;
  for (int e = 0; e < static_cast<int>(s.graph.edges.size()); ++e) {
    if (s.perturbed.count(e)) continue;
    const ViewGraphEdge& g = s.graph.edges[e];
    const double d = RotationDifferenceDeg(g.rotation, s.truth[g.cam_b] * s.truth[g.cam_a].conjugate());
    sum += d * d;
    ++count;
  }
  return std::sqrt(sum / count);
}

TEST(RotationAveraging, ExactGraphIsRecoveredExactly) {
  std::mt19937 rng = TestRng();  // seeded from the test's name: reproducible, independent
  const SyntheticGraph s = MakeGraph(rng, 8, 0.0, 0.0);
  const RotationAveragingResult r = AverageRotations(s.graph, 0, {});
  ASSERT_EQ(r.cam_from_rig.size(), 8u);
  EXPECT_LT(RotationDifferenceDeg(*r.cam_from_rig[0], Eigen::Quaterniond::Identity()), 1e-12);  // the gauge
  EXPECT_LT(MaxRelativeError(r, s.truth), 1e-6);
  EXPECT_EQ(r.num_outliers, 0);
}

TEST(RotationAveraging, TwentyCamerasWithThirtyPercentOutlierEdges) {
  std::mt19937 rng = TestRng();
  const double noise_deg = 0.3;
  const SyntheticGraph s = MakeGraph(rng, 20, noise_deg, 0.3);
  ASSERT_GT(s.perturbed.size(), 40u);
  const RotationAveragingResult r = AverageRotations(s.graph, 0, {});
  for (int c = 0; c < 20; ++c) ASSERT_TRUE(r.cam_from_rig[c].has_value()) << c;
  // About 13 good edges per camera: the averaged relative rotations are several times better than
  // a single edge (0.3 deg per axis, ~0.5 deg RMS), and even the worst pair is no worse than that.
  double rms = 0.0;
  const double err = MaxRelativeError(r, s.truth, &rms);
  const double edge_rms = InlierEdgeRms(s);
  EXPECT_LT(rms, 0.5 * edge_rms) << "edge RMS " << edge_rms;
  EXPECT_LT(err, 1.2 * edge_rms) << "edge RMS " << edge_rms;
  std::set<int> flagged;
  for (int e = 0; e < static_cast<int>(r.outlier.size()); ++e) {
    if (r.outlier[e]) flagged.insert(e);
  }
  EXPECT_EQ(flagged, s.perturbed);
  RecordProperty("max_relative_error_deg", std::to_string(err));
  RecordProperty("rms_relative_error_deg", std::to_string(rms));
  std::printf("rotation averaging: edge RMS %.3f deg, result RMS %.3f deg, max %.3f deg\n", edge_rms, rms, err);
}

TEST(RotationAveraging, OnlyTheReferenceComponentIsSolved) {
  std::mt19937 rng = TestRng();
  SyntheticGraph s = MakeGraph(rng, 4, 0.0, 0.0);
  // Cut camera 3 off: deactivate its edges.
  for (int e = 0; e < static_cast<int>(s.graph.edges.size()); ++e) {
    if (s.graph.edges[e].cam_a == 3 || s.graph.edges[e].cam_b == 3) s.graph.Deactivate(e, "test");
  }
  const RotationAveragingResult r = AverageRotations(s.graph, 0, {});
  EXPECT_TRUE(r.cam_from_rig[2].has_value());
  EXPECT_FALSE(r.cam_from_rig[3].has_value());
}

TEST(RotationAveraging, ChainWithoutLoopsFollowsTheEdges) {
  std::mt19937 rng = TestRng();
  std::vector<Eigen::Quaterniond> truth = {Eigen::Quaterniond::Identity(), RandomRotation(rng), RandomRotation(rng)};
  std::vector<PairEstimate> pairs;
  for (int a = 0; a < 2; ++a) {
    PairEstimate p;
    p.cam_a = a;
    p.cam_b = a + 1;
    p.two_view.success = true;
    p.two_view.num_inliers = 100;
    p.two_view.cam_b_from_cam_a = Rigid3d(truth[a + 1] * truth[a].conjugate(), Eigen::Vector3d(1, 0, 0));
    pairs.push_back(p);
  }
  const RotationAveragingResult r = AverageRotations(BuildViewGraph(3, pairs, {}), 0, {});
  for (int c = 0; c < 3; ++c) EXPECT_LT(RotationDifferenceDeg(*r.cam_from_rig[c], truth[c]), 1e-9);
}

}  // namespace
}  // namespace rigsim
