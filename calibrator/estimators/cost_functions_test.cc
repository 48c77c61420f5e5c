#include "calibrator/estimators/cost_functions.h"

#include <memory>
#include <random>

#include <gtest/gtest.h>

#include "geometry/rigid3.h"

namespace rigsim {
namespace {

const Camera kCameras[] = {
    Camera(CameraModelId::kPinhole, 640, 480, {300, 310, 320, 240}),
    Camera(CameraModelId::kOpenCV, 640, 480, {300, 310, 320, 240, -0.1, 0.02, 0.001, -0.002}),
    Camera(CameraModelId::kFullOpenCV, 640, 480, {300, 310, 320, 240, -0.1, 0.02, 0.001, -0.002, 0.001, 0.01, 0, 0}),
    Camera(CameraModelId::kOpenCVFisheye, 640, 480, {200, 200, 320, 240, 0.02, -0.01, 0.002, 0.0})};

// One observation's parameters: cam_from_rig, rig_from_world, a point 3-6 m in front of the
// camera (in the world), and the camera's intrinsics.
struct Observation {
  std::vector<std::vector<double>> blocks;  // 4, 3, 4, 3, 3, intrinsics
  Eigen::Vector2d observed;

  std::vector<const double*> Pointers() const {
    std::vector<const double*> p;
    for (const auto& b : blocks) p.push_back(b.data());
    return p;
  }
};

Observation RandomObservation(const Camera& cam, std::mt19937& rng) {
  std::normal_distribution<double> g(0, 1);
  auto random_pose = [&] {
    return Rigid3d(Eigen::Quaterniond(1, 0.1 * g(rng), 0.1 * g(rng), 0.1 * g(rng)).normalized(),
                   0.3 * Eigen::Vector3d(g(rng), g(rng), g(rng)));
  };
  const Rigid3d cam_from_rig = random_pose(), rig_from_world = random_pose();
  const Eigen::Vector3d x_in_cam(g(rng), 0.5 * g(rng), 3 + 3 * std::abs(g(rng)));
  const Eigen::Vector3d x = (cam_from_rig * rig_from_world).Inverse() * x_in_cam;
  auto vec = [](const auto& v) { return std::vector<double>(v.data(), v.data() + v.size()); };
  Observation o;
  o.blocks = {vec(cam_from_rig.rotation.coeffs()), vec(cam_from_rig.translation), vec(rig_from_world.rotation.coeffs()),
              vec(rig_from_world.translation), vec(x), cam.params()};
  o.observed = Eigen::Vector2d(300 + 10 * g(rng), 250 + 10 * g(rng));
  return o;
}

// Residual and row-major Jacobians per block; `with_intrinsics` false asks for none of the
// intrinsics block, as Ceres does while the block is held constant.
bool Evaluate(const ceres::CostFunction& cost, const Observation& o, bool with_intrinsics, Eigen::Vector2d* residual,
              std::vector<std::vector<double>>* jacobians) {
  jacobians->clear();
  std::vector<double*> j;
  for (const auto& b : o.blocks) {
    jacobians->emplace_back(2 * b.size(), 0.0);
    j.push_back(jacobians->back().data());
  }
  if (!with_intrinsics) j[5] = nullptr;
  return cost.Evaluate(o.Pointers().data(), residual->data(), j.data());
}

Eigen::Vector2d Residual(const ceres::CostFunction& cost, const Observation& o) {
  Eigen::Vector2d r;
  EXPECT_TRUE(cost.Evaluate(o.Pointers().data(), r.data(), nullptr));
  return r;
}

// The Jacobian of every block against central differences of the residual itself; with the
// intrinsics held constant, and with them varying (what refining intrinsics will need).
TEST(RigReprojectionCost, JacobiansMatchFiniteDifferencesWithIntrinsicsHeldOrFree) {
  std::mt19937 rng(12345);
  for (const Camera& cam : kCameras) {
    SCOPED_TRACE(std::string(CameraModelName(cam.model())));
    for (int trial = 0; trial < 5; ++trial) {
      Observation o = RandomObservation(cam, rng);
      if (trial >= 3) {  // quaternions off unit norm: the cost rotates by Eigen's formula as written
        for (double& v : o.blocks[0]) v *= 1.05;
        for (double& v : o.blocks[2]) v *= 0.97;
      }
      const std::unique_ptr<ceres::CostFunction> cost(CreateRigReprojectionCost(cam, o.observed));
      ASSERT_EQ(cost->parameter_block_sizes().back(), static_cast<int>(cam.params().size()));
      Eigen::Vector2d r_held, r_free;
      std::vector<std::vector<double>> j_held, j_free;
      ASSERT_TRUE(Evaluate(*cost, o, false, &r_held, &j_held));
      ASSERT_TRUE(Evaluate(*cost, o, true, &r_free, &j_free));
      EXPECT_LT((Residual(*cost, o) - r_held).norm(), 1e-12);
      EXPECT_LT((r_free - r_held).norm(), 1e-12);
      for (size_t b = 0; b < o.blocks.size(); ++b) {
        for (size_t i = 0; i < o.blocks[b].size(); ++i) {
          const double h = 1e-6;
          Observation plus = o, minus = o;
          plus.blocks[b][i] += h;
          minus.blocks[b][i] -= h;
          const Eigen::Vector2d numeric = (Residual(*cost, plus) - Residual(*cost, minus)) / (2 * h);
          for (int row = 0; row < 2; ++row) {
            const double analytic = j_free[b][row * o.blocks[b].size() + i];
            EXPECT_NEAR(analytic, numeric[row], 1e-5 * std::max(1.0, std::abs(analytic))) << "block " << b << " " << i;
            if (b < 5) {  // the pose and point blocks: the same derivatives either way
              EXPECT_NEAR(j_held[b][row * o.blocks[b].size() + i], analytic, 1e-12 * std::max(1.0, std::abs(analytic)));
            }
          }
        }
      }
    }
  }
}

TEST(RigReprojectionCost, PointBehindAPerspectiveCameraDoesNotProject) {
  std::mt19937 rng(7);
  Observation o = RandomObservation(kCameras[0], rng);
  o.blocks[0] = {0, 0, 0, 1};
  o.blocks[1] = {0, 0, 0};
  o.blocks[2] = {0, 0, 0, 1};
  o.blocks[3] = {0, 0, 0};
  o.blocks[4] = {0.1, 0.2, -3.0};
  const std::unique_ptr<ceres::CostFunction> cost(CreateRigReprojectionCost(kCameras[0], o.observed));
  Eigen::Vector2d r;
  std::vector<std::vector<double>> j;
  EXPECT_FALSE(Evaluate(*cost, o, false, &r, &j));
}

TEST(EpipolarAngularCost, ZeroForANoiseFreeCorrespondence) {
  const Rigid3d b_from_a(Eigen::Quaterniond(Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitY())), Eigen::Vector3d(1, 0, 0));
  const Eigen::Vector3d x_in_a(0.4, -0.2, 5.0);
  const Eigen::Vector3d fa = x_in_a.normalized(), fb = (b_from_a * x_in_a).normalized();
  const EpipolarAngularCost cost(fa, fb);
  Eigen::Vector2d r;
  ASSERT_TRUE(cost(b_from_a.rotation.coeffs().data(), b_from_a.translation.data(), r.data()));
  EXPECT_LT(r.norm(), 1e-12);
}

TEST(RelativeRotationCost, ZeroAtTheTruthAndTheAngleOtherwise) {
  const Eigen::Quaterniond ra(Eigen::AngleAxisd(0.2, Eigen::Vector3d::UnitX()));
  const Eigen::Quaterniond rb(Eigen::AngleAxisd(0.5, Eigen::Vector3d::UnitZ()));
  const RelativeRotationCost exact(rb * ra.conjugate(), 2.0);
  Eigen::Vector3d r;
  ASSERT_TRUE(exact(ra.coeffs().data(), rb.coeffs().data(), r.data()));
  EXPECT_LT(r.norm(), 1e-12);
  const RelativeRotationCost off(Eigen::Quaterniond(Eigen::AngleAxisd(0.1, Eigen::Vector3d::UnitY())) * rb * ra.conjugate(),
                                 2.0);
  ASSERT_TRUE(off(ra.coeffs().data(), rb.coeffs().data(), r.data()));
  EXPECT_NEAR(r.norm(), 2.0 * 0.1, 1e-9);  // weight x angle
}

}  // namespace
}  // namespace rigsim
