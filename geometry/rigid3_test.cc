#include "geometry/rigid3.h"

#include <gtest/gtest.h>

namespace rigsim {
namespace {

Rigid3d RandomPose(int seed) {
  std::srand(seed);
  return Rigid3d(Eigen::Quaterniond::UnitRandom(), Eigen::Vector3d::Random() * 3.0);
}

TEST(Rigid3d, MeanOfNearbyPosesTurnsHalfWayAndIgnoresTheQuaternionSign) {
  const Eigen::Vector3d axis = Eigen::Vector3d(1, 2, 3).normalized();
  const Rigid3d a(Eigen::Quaterniond(Eigen::AngleAxisd(0.1, axis)), Eigen::Vector3d(1, 0, 0));
  Rigid3d b(Eigen::Quaterniond(Eigen::AngleAxisd(0.3, axis)), Eigen::Vector3d(3, 2, 0));
  b.rotation.coeffs() *= -1.0;  // the same rotation from the other side of the sphere
  const Rigid3d mean = MeanOfNearbyPoses({a, b});
  EXPECT_LT(RotationDifferenceDeg(mean.rotation, Eigen::Quaterniond(Eigen::AngleAxisd(0.2, axis))), 1e-9);
  EXPECT_LT((mean.translation - Eigen::Vector3d(2, 1, 0)).norm(), 1e-12);
  EXPECT_LT(RotationDifferenceDeg(MeanOfNearbyPoses({}).rotation, Eigen::Quaterniond::Identity()), 1e-12);
}

TEST(Rigid3d, InverseUndoesTransform) {
  const Rigid3d a_from_b = RandomPose(1);
  const Eigen::Vector3d x(0.3, -1.2, 4.0);
  EXPECT_LT((a_from_b.Inverse() * (a_from_b * x) - x).norm(), 1e-12);
}

TEST(Rigid3d, CompositionFollowsTargetFromSourceNaming) {
  const Rigid3d cam_from_rig = RandomPose(2);
  const Rigid3d rig_from_world = RandomPose(3);
  const Eigen::Vector3d x_in_world(1.0, 2.0, 3.0);
  const Rigid3d cam_from_world = cam_from_rig * rig_from_world;
  EXPECT_LT((cam_from_world * x_in_world - cam_from_rig * (rig_from_world * x_in_world)).norm(), 1e-12);
}

TEST(Rigid3d, SourceOriginInTargetIsCameraCentre) {
  const Rigid3d cam_from_world = RandomPose(4);
  const Eigen::Vector3d centre = cam_from_world.SourceOriginInTarget();
  EXPECT_LT((cam_from_world * centre).norm(), 1e-12);
}

TEST(Rigid3d, RotationDifferenceIsTheAngleOfTheRelativeRotation) {
  const Eigen::Quaterniond a(Eigen::AngleAxisd(0.3, Eigen::Vector3d(1, 2, 3).normalized()));
  const Eigen::Quaterniond b = Eigen::Quaterniond(Eigen::AngleAxisd(DegToRad(1.0), Eigen::Vector3d::UnitY())) * a;
  EXPECT_NEAR(RotationDifferenceDeg(a, b), 1.0, 1e-9);
  EXPECT_NEAR(RotationDifferenceDeg(a, a), 0.0, 1e-12);
  // q and -q are the same rotation.
  const Eigen::Quaterniond neg(-a.w(), -a.x(), -a.y(), -a.z());
  EXPECT_NEAR(RotationDifferenceDeg(a, neg), 0.0, 1e-9);
  const Eigen::Quaterniond flip(Eigen::AngleAxisd(DegToRad(179.0), Eigen::Vector3d::UnitZ()));
  EXPECT_NEAR(RotationDifferenceDeg(flip, Eigen::Quaterniond::Identity()), 179.0, 1e-9);
}

TEST(Rigid3d, AngleBetween) {
  EXPECT_NEAR(AngleBetweenDeg(Eigen::Vector3d(1, 0, 0), Eigen::Vector3d(0, 2, 0)), 90.0, 1e-12);
  EXPECT_NEAR(AngleBetweenDeg(Eigen::Vector3d(1, 0, 0), Eigen::Vector3d(-3, 0, 0)), 180.0, 1e-12);
}

// glTF cameras look down -Z with +Y up; ours look down +Z with +Y down.
TEST(Rigid3d, CrossProductMatrixTimesAVectorIsTheCrossProduct) {
  const Eigen::Vector3d v(0.3, -1.2, 2.5), w(-0.7, 0.4, 1.1);
  EXPECT_LT((CrossProductMatrix(v) * w - v.cross(w)).norm(), 1e-15);
  EXPECT_LT((CrossProductMatrix(v) + CrossProductMatrix(v).transpose()).norm(), 1e-15);  // skew
  EXPECT_LT((CrossProductMatrix(v) * v).norm(), 1e-15);
}

TEST(GltfCamera, IdentityNodeLooksDownMinusZWithYUp) {
  const Rigid3d cam_from_world = CamFromWorldFromGltfCameraNode(Eigen::Matrix4d::Identity());
  const Eigen::Vector3d ahead = cam_from_world * Eigen::Vector3d(0, 0, -5);
  EXPECT_LT((ahead - Eigen::Vector3d(0, 0, 5)).norm(), 1e-12);
  EXPECT_GT((cam_from_world * Eigen::Vector3d(1, 0, -5)).x(), 0.0);  // world right = image right
  EXPECT_LT((cam_from_world * Eigen::Vector3d(0, 1, -5)).y(), 0.0);  // world up = image up (y down)
}

TEST(GltfCamera, NodeTranslationAndScaleAreHandled) {
  Eigen::Matrix4d world_from_glcam = Eigen::Matrix4d::Identity();
  // Camera at (2, 1, 0) turned 90 deg left (about +Y): it looks down world -X. Scale 3 is ignored.
  world_from_glcam.topLeftCorner<3, 3>() = 3.0 * Eigen::AngleAxisd(DegToRad(90), Eigen::Vector3d::UnitY()).matrix();
  world_from_glcam.topRightCorner<3, 1>() = Eigen::Vector3d(2, 1, 0);
  const Rigid3d cam_from_world = CamFromWorldFromGltfCameraNode(world_from_glcam);
  EXPECT_LT((cam_from_world.SourceOriginInTarget() - Eigen::Vector3d(2, 1, 0)).norm(), 1e-12);
  EXPECT_LT((cam_from_world * Eigen::Vector3d(-3, 1, 0) - Eigen::Vector3d(0, 0, 5)).norm(), 1e-12);
}

}  // namespace
}  // namespace rigsim
