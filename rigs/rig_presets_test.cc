#include "rigs/rig_presets.h"

#include <cmath>

#include <Eigen/Core>
#include <gtest/gtest.h>

namespace rigsim {
namespace {

Eigen::Vector3d Centre(const RigCamera& c) { return c.cam_from_rig->Inverse().translation; }
Eigen::Vector3d Axis(const RigCamera& c) { return c.cam_from_rig->Inverse().rotation * Eigen::Vector3d::UnitZ(); }

TEST(RingRig, CamerasFaceOutwardsFromLeftToRight) {
  RingRigOptions o;
  o.num_cameras = 4;
  o.yaw_spacing_deg = 60;
  const Rig rig = MakeRingRig(o);
  ASSERT_EQ(rig.cameras.size(), 4u);
  double previous_yaw = -1e9;
  for (const RigCamera& c : rig.cameras) {
    const Rigid3d rig_from_cam = c.cam_from_rig->Inverse();
    const Eigen::Vector3d axis = rig_from_cam.rotation * Eigen::Vector3d::UnitZ();
    const Eigen::Vector3d centre = rig_from_cam.translation;
    EXPECT_NEAR(centre.norm(), o.radius_m, 1e-12);
    EXPECT_NEAR(axis.y(), 0.0, 1e-12);                            // horizontal
    EXPECT_LT((axis - centre.normalized()).norm(), 1e-12);        // facing outwards
    const double yaw = RadToDeg(std::atan2(axis.x(), axis.z()));  // + = right
    EXPECT_GT(yaw, previous_yaw);
    if (previous_yaw > -1e9) {
      EXPECT_NEAR(yaw - previous_yaw, 60.0, 1e-9);
    }
    previous_yaw = yaw;
    // Image y stays down.
    EXPECT_LT((rig_from_cam.rotation * Eigen::Vector3d::UnitY() - Eigen::Vector3d::UnitY()).norm(), 1e-12);
  }
}

TEST(RingRig, DistortedCameraKeepsTheFieldOfView) {
  RingRigOptions o;
  const Rig rig = MakeRingRig(o);
  const Camera& barrel = rig.cameras[o.distorted_camera].camera;
  const Camera& pinhole = rig.cameras[0].camera;
  EXPECT_EQ(barrel.model(), CameraModelId::kOpenCV);
  const double half = DegToRad(o.hfov_deg / 2);
  const Eigen::Vector3d edge_ray(std::sin(half), 0.0, std::cos(half));
  EXPECT_NEAR(barrel.ImgFromCam(edge_ray)->x(), o.width - 0.5, 1e-9);
  EXPECT_NEAR(pinhole.ImgFromCam(edge_ray)->x(), o.width - 0.5, 1e-9);
  // The whole sensor is imaged.
  EXPECT_TRUE(barrel.CamFromImg(Eigen::Vector2d(-0.5, -0.5)).has_value());
}

TEST(RingRig, TargetOverlapSetsTheSpacing) {
  for (double target : {0.1, 0.3, 0.5}) {
    RingRigOptions o;
    o.num_cameras = 3;
    o.distorted_camera = -1;
    const double spacing = RingSpacingForOverlap(o, target);
    // Independent check in normalised coordinates: a pinhole point (u, v) of camera a, rotated
    // about y by the spacing, is seen by b when |u_b| <= tan(h/2) and |v_b| <= tan(vfov/2).
    const double tu = std::tan(DegToRad(o.hfov_deg / 2)), tv = tu * o.height / o.width, s = DegToRad(spacing);
    int seen = 0, total = 0;
    for (int j = 0; j < 225; ++j) {
      for (int i = 0; i < 400; ++i, ++total) {
        const double u = tu * ((i + 0.5) / 200 - 1), v = tv * ((j + 0.5) / 112.5 - 1);
        const double z = u * std::sin(s) + std::cos(s);
        if (z > 0 && std::abs((u * std::cos(s) - std::sin(s)) / z) <= tu && std::abs(v / z) <= tv) ++seen;
      }
    }
    EXPECT_NEAR(double(seen) / total, target, 0.01) << "spacing " << spacing;
    o.target_overlap = target;
    const Rig rig = MakeRingRig(o);
    const double yaw0 = std::atan2(Axis(rig.cameras[0]).x(), Axis(rig.cameras[0]).z());
    const double yaw1 = std::atan2(Axis(rig.cameras[1]).x(), Axis(rig.cameras[1]).z());
    EXPECT_NEAR(RadToDeg(yaw1 - yaw0), spacing, 1e-6);
  }
  RingRigOptions o;
  o.target_overlap = 0.99;
  o.distorted_camera = -1;
  EXPECT_GT(AngularOverlap(MakeRingRig(o).cameras[0].camera, MakeRingRig(o).cameras[1].camera, Eigen::Matrix3d::Identity()), 0.99);
}

TEST(StereoRig, BaselineAndParallelAxes) {
  StereoRigOptions o;
  o.baseline_m = 0.3;
  const Rig rig = MakeStereoRig(o);
  ASSERT_EQ(rig.cameras.size(), 2u);
  EXPECT_EQ(rig.cameras[0].name, "left");
  EXPECT_NEAR((Centre(rig.cameras[1]) - Centre(rig.cameras[0])).norm(), 0.3, 1e-12);
  EXPECT_GT(Centre(rig.cameras[1]).x(), Centre(rig.cameras[0]).x());  // right is at +x
  EXPECT_LT((Axis(rig.cameras[0]) - Axis(rig.cameras[1])).norm(), 1e-12);
}

TEST(SurroundRig, MixedModelsAndFisheyeBeyond180) {
  SurroundRigOptions o;
  const Rig rig = MakeSurroundRig(o);
  ASSERT_EQ(rig.cameras.size(), 4u);
  EXPECT_EQ(rig.cameras[0].camera.model(), CameraModelId::kOpenCV);
  EXPECT_EQ(rig.cameras[1].camera.model(), CameraModelId::kOpenCVFisheye);
  EXPECT_EQ(rig.cameras[2].camera.model(), CameraModelId::kPinhole);
  EXPECT_EQ(rig.cameras[3].camera.model(), CameraModelId::kOpenCVFisheye);
  // The right fisheye images the ray 95 deg off its axis at its right image edge.
  const Camera& fish = rig.cameras[1].camera;
  const double theta = DegToRad(o.side_fov_deg / 2);
  const auto px = fish.ImgFromCam(Eigen::Vector3d(std::sin(theta), 0, std::cos(theta)));
  ASSERT_TRUE(px.has_value());
  EXPECT_NEAR(px->x(), fish.width() - 0.5, 1e-6);
  EXPECT_GT(RadToDeg(fish.max_valid_angle()), 95.0);
  // Directions: front +z, right +x, back -z, left -x in the rig frame.
  EXPECT_NEAR(Axis(rig.cameras[0]).z(), 1, 1e-12);
  EXPECT_NEAR(Axis(rig.cameras[1]).x(), 1, 1e-12);
  EXPECT_NEAR(Axis(rig.cameras[2]).z(), -1, 1e-12);
  EXPECT_NEAR(Axis(rig.cameras[3]).x(), -1, 1e-12);
  EXPECT_NEAR(Centre(rig.cameras[0]).z(), 2.0, 1e-12);
}

TEST(WideBaselineRig, BaselineAndConvergence) {
  WideBaselineRigOptions o;
  o.baseline_m = 3.0;
  o.convergence_deg = 40.0;
  const Rig rig = MakeWideBaselineRig(o);
  EXPECT_NEAR((Centre(rig.cameras[1]) - Centre(rig.cameras[0])).norm(), 3.0, 1e-12);
  EXPECT_NEAR(AngleBetweenDeg(Axis(rig.cameras[0]), Axis(rig.cameras[1])), 40.0, 1e-9);
  // Toed in: the axes meet in front of the rig.
  EXPECT_GT(Axis(rig.cameras[0]).x(), 0);
  EXPECT_LT(Axis(rig.cameras[1]).x(), 0);
}

TEST(RigPerturbation, SeededAndBounded) {
  Rig a = MakeStereoRig({}), b = MakeStereoRig({}), ref = MakeStereoRig({});
  PerturbRig(a, {2.0, 0.01, 7});
  PerturbRig(b, {2.0, 0.01, 7});
  for (size_t i = 0; i < a.cameras.size(); ++i) {
    EXPECT_EQ(a.cameras[i].cam_from_rig->translation, b.cameras[i].cam_from_rig->translation);
    const double rot = RotationDifferenceDeg(a.cameras[i].cam_from_rig->rotation, ref.cameras[i].cam_from_rig->rotation);
    EXPECT_GT(rot, 0.0);
    EXPECT_LE(rot, 2.0 + 1e-9);
  }
}

}  // namespace
}  // namespace rigsim
