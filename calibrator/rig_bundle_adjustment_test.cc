#include "calibrator/rig_bundle_adjustment.h"

#include <cmath>
#include <random>

#include <gtest/gtest.h>

namespace rigsim {
namespace {

std::mt19937 TestRng() {
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  uint32_t h = 2166136261u;  // FNV-1a of the test's name
  for (char c : std::string(info->test_suite_name()) + "." + info->name()) h = (h ^ static_cast<uint8_t>(c)) * 16777619u;
  return std::mt19937(h);
}

TEST(BuildTracks, JoinsPairsAndDropsContradictions) {
  // Frame 0: 0:5 - 1:7 - 2:9 form one track through two pairs; 0:1 - 1:2 and 1:2 - 2:3 and
  // 0:4 - 2:3 put keypoints 1 and 4 of camera 0 in one set: contradictory.
  PairMatches p01{0, 1, {{{5, 7}, {1, 2}}, {{0, 0}}}};
  PairMatches p12{1, 2, {{{7, 9}, {2, 3}}, {}}};
  PairMatches p02{0, 2, {{{4, 3}}, {}}};
  int conflicting = -1;
  const std::vector<Track> tracks = BuildTracks(3, 2, {p01, p12, p02}, &conflicting);
  EXPECT_EQ(conflicting, 1);
  ASSERT_EQ(tracks.size(), 2u);
  EXPECT_EQ(tracks[0].frame, 0);
  ASSERT_EQ(tracks[0].observations.size(), 3u);
  EXPECT_EQ(tracks[0].observations[0].camera, 0);
  EXPECT_EQ(tracks[0].observations[0].keypoint, 5);
  EXPECT_EQ(tracks[0].observations[2].camera, 2);
  EXPECT_EQ(tracks[0].observations[2].keypoint, 9);
  EXPECT_EQ(tracks[1].frame, 1);  // frames never mix: keypoint 0 of frame 1 is another point
  EXPECT_EQ(tracks[1].observations.size(), 2u);
  EXPECT_THROW(BuildTracks(3, 3, {p01}), std::invalid_argument);
  EXPECT_THROW(BuildTracks(1, 2, {p01}), std::invalid_argument);
}

// A view graph from true rotations and centres (directions exact).
ViewGraph GraphFromTruth(const std::vector<Rigid3d>& cam_from_rig, const std::vector<std::pair<int, int>>& pairs) {
  std::vector<PairEstimate> estimates;
  for (auto [a, b] : pairs) {
    PairEstimate p;
    p.cam_a = a;
    p.cam_b = b;
    p.success = true;
    p.num_inliers = 100;
    const Rigid3d rel = cam_from_rig[b] * cam_from_rig[a].Inverse();
    p.cam_b_from_cam_a = Rigid3d(rel.rotation, rel.translation.normalized());
    estimates.push_back(p);
  }
  return BuildViewGraph(static_cast<int>(cam_from_rig.size()), estimates, {});
}

std::vector<Rigid3d> RandomRig(std::mt19937& rng, int n) {
  std::normal_distribution<double> g(0, 1);
  std::vector<Rigid3d> rig(n);
  for (int c = 1; c < n; ++c) {
    const Eigen::Quaterniond q = Eigen::Quaterniond(g(rng), g(rng), g(rng), g(rng)).normalized();
    const Eigen::Vector3d centre(g(rng), g(rng), g(rng));
    rig[c] = Rigid3d(q, -(q * centre));
  }
  return rig;
}

TEST(EstimateCameraCentres, ExactDirectionsGiveTheShape) {
  std::mt19937 rng = TestRng();
  const std::vector<Rigid3d> rig = RandomRig(rng, 5);
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
  const std::vector<Rigid3d> rig = RandomRig(rng, 4);
  ViewGraph graph = GraphFromTruth(rig, {{0, 1}, {1, 2}, {0, 2}, {2, 3}});
  graph.edges[3].rotation_only = true;
  graph.edges[3].direction.setZero();
  std::vector<std::optional<Eigen::Quaterniond>> rot;
  for (const Rigid3d& r : rig) rot.push_back(r.rotation);
  const CameraCentres c = EstimateCameraCentres(graph, rot, 0);
  EXPECT_TRUE(c.centre_in_rig[2].has_value());
  EXPECT_FALSE(c.centre_in_rig[3].has_value());
}

TEST(TriangulateTrack, RaysMeetAtThePoint) {
  const Camera cam(CameraModelId::kPinhole, 640, 480, {300, 300, 320, 240});
  const std::vector<Camera> cameras = {cam, cam};
  const std::vector<std::optional<Rigid3d>> poses = {Rigid3d(),
                                                     Rigid3d(Eigen::Quaterniond::Identity(), Eigen::Vector3d(-0.5, 0, 0))};
  const Eigen::Vector3d x(0.3, -0.2, 4.0);
  FrameKeypoints kps(1, std::vector<std::vector<Eigen::Vector2d>>(2));
  kps[0][0].push_back(*cam.ImgFromCam(*poses[0] * x));
  kps[0][1].push_back(*cam.ImgFromCam(*poses[1] * x));
  const Track track{0, {{0, 0}, {1, 0}}};
  const auto p = TriangulateTrack(cameras, kps, track, poses, DegToRad(1.0));
  ASSERT_TRUE(p.has_value());
  EXPECT_LT((*p - x).norm(), 1e-9);
  // The rays meet at about 7 deg: a 10 deg minimum rejects the track.
  EXPECT_FALSE(TriangulateTrack(cameras, kps, track, poses, DegToRad(10.0)).has_value());
}

// The autodiff Jacobian of the bundle adjustment's residual equals central differences of the
// same residual, for every camera model, in all 10 parameters.
TEST(RigReprojectionResidual, AutodiffJacobianMatchesFiniteDifferences) {
  std::mt19937 rng = TestRng();
  std::normal_distribution<double> g(0, 1);
  const Camera cameras[] = {
      Camera(CameraModelId::kPinhole, 640, 480, {300, 310, 320, 240}),
      Camera(CameraModelId::kOpenCV, 640, 480, {300, 310, 320, 240, -0.1, 0.02, 0.001, -0.002}),
      Camera(CameraModelId::kFullOpenCV, 640, 480, {300, 310, 320, 240, -0.1, 0.02, 0.001, -0.002, 0.001, 0.01, 0, 0}),
      Camera(CameraModelId::kOpenCVFisheye, 640, 480, {200, 200, 320, 240, 0.02, -0.01, 0.002, 0.0})};
  for (const Camera& cam : cameras) {
    SCOPED_TRACE(std::string(CameraModelName(cam.model())));
    for (int trial = 0; trial < 5; ++trial) {
      const Eigen::Quaterniond q = Eigen::Quaterniond(1, 0.1 * g(rng), 0.1 * g(rng), 0.1 * g(rng)).normalized();
      const Eigen::Vector3d t = 0.3 * Eigen::Vector3d(g(rng), g(rng), g(rng));
      // A point 3-6 m in front of the camera, expressed in the rig frame.
      const Eigen::Vector3d x_in_cam(g(rng), 0.5 * g(rng), 3 + 3 * std::abs(g(rng)));
      const Eigen::Vector3d x = q.conjugate() * (x_in_cam - t);
      const Eigen::Vector2d observed(300 + 10 * g(rng), 250 + 10 * g(rng));
      Eigen::Vector2d r;
      Eigen::Matrix<double, 2, 4> jq;
      Eigen::Matrix<double, 2, 3> jt, jx;
      Eigen::Vector4d qv = q.coeffs();
      ASSERT_TRUE(EvaluateRigReprojection(cam, observed, qv, t, x, &r, &jq, &jt, &jx));
      const RigReprojectionResidual functor(cam, observed);
      // Central differences over the stacked parameters [q (4), t (3), x (3)].
      Eigen::Matrix<double, 10, 1> params;
      params << qv, t, x;
      auto eval = [&](const Eigen::Matrix<double, 10, 1>& p) {
        Eigen::Vector2d out;
        EXPECT_TRUE(functor(p.data(), p.data() + 4, p.data() + 7, out.data()));
        return out;
      };
      EXPECT_LT((eval(params) - r).norm(), 1e-12);
      Eigen::Matrix<double, 2, 10> numeric, analytic;
      analytic << jq, jt, jx;
      const double h = 1e-6;
      for (int k = 0; k < 10; ++k) {
        Eigen::Matrix<double, 10, 1> plus = params, minus = params;
        plus(k) += h;
        minus(k) -= h;
        numeric.col(k) = (eval(plus) - eval(minus)) / (2 * h);
      }
      EXPECT_LT((numeric - analytic).cwiseAbs().maxCoeff(), 1e-5 * std::max(1.0, analytic.cwiseAbs().maxCoeff()))
          << "analytic\n" << analytic << "\nnumeric\n" << numeric;
    }
  }
}

TEST(RigBundleAdjustmentOptions, CheckNamesTheField) {
  RigBundleAdjustmentOptions o;
  o.loss_scale_px = 0;
  try {
    o.Check();
    ADD_FAILURE();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("loss_scale_px"), std::string::npos);
  }
}

}  // namespace
}  // namespace rigsim
