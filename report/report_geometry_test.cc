#include "report/report_geometry.h"

#include <cmath>

#include <gtest/gtest.h>

namespace rigsim {
namespace {

Camera Pinhole() { return Camera(CameraModelId::kPinhole, 640, 480, {500, 500, 319.5, 239.5}); }
Camera Distorted() { return Camera(CameraModelId::kOpenCV, 640, 480, {400, 400, 319.5, 239.5, -0.25, 0.06, 0, 0}); }
Camera Fisheye() {
  return Camera(CameraModelId::kOpenCVFisheye, 640, 480, {120, 120, 319.5, 239.5, 0.0, 0.0, 0.0, 0.0});
}

TEST(FieldOfViewOutline, PinholeCornersAreTheImageCorners) {
  const Camera cam = Pinhole();
  const auto rays = FieldOfViewOutline(cam, 4);
  ASSERT_EQ(rays.size(), 16u);
  const auto px = cam.ImgFromCam(rays[0]);  // the top-left corner first
  ASSERT_TRUE(px);
  EXPECT_NEAR(px->x(), -0.5, 1e-6);
  EXPECT_NEAR(px->y(), -0.5, 1e-6);
  for (const auto& r : rays) EXPECT_NEAR(r.norm(), 1.0, 1e-9);
}

TEST(FieldOfViewOutline, FisheyeCornersWithoutARayStopAtTheLensLimit) {
  // 120 px per radian: the corners (400 px from the centre) lie beyond theta = pi.
  const Camera cam = Fisheye();
  ASSERT_FALSE(cam.CamFromImg({-0.5, -0.5}));
  const auto rays = FieldOfViewOutline(cam, 8);
  ASSERT_EQ(rays.size(), 32u);
  double widest = 0.0;
  for (const auto& r : rays) widest = std::max(widest, std::acos(std::clamp(r.z(), -1.0, 1.0)));
  EXPECT_NEAR(widest, cam.max_valid_angle(), 1e-3);
}

TEST(EpipolarCurve, PinholePointsLieOnTheEpipolarLine) {
  const Camera cam = Pinhole();
  const Rigid3d b_from_a(Eigen::Quaterniond(Eigen::AngleAxisd(0.2, Eigen::Vector3d::UnitY())), Eigen::Vector3d(-0.5, 0.02, 0.1));
  const Eigen::Vector2d px(300, 200);
  const auto curve = EpipolarCurve(cam, px, cam, b_from_a, EpipolarDepths(0.5, 100, 20));
  ASSERT_EQ(curve.size(), 21u);  // the depths and infinity
  // The essential matrix: x_b^T [t]x R x_a = 0 for normalised coordinates.
  Eigen::Matrix3d tx;
  const Eigen::Vector3d t = b_from_a.translation;
  tx << 0, -t.z(), t.y(), t.z(), 0, -t.x(), -t.y(), t.x(), 0;
  const Eigen::Matrix3d e = tx * b_from_a.rotation.toRotationMatrix();
  const Eigen::Vector3d xa = *cam.CamFromImg(px);
  int seen = 0;
  for (const auto& p : curve) {
    if (!p) continue;
    ++seen;
    const Eigen::Vector3d xb = *cam.CamFromImg(*p);
    EXPECT_NEAR(xb.dot(e * xa), 0.0, 1e-9);
  }
  EXPECT_GE(seen, 15);
}

TEST(EpipolarCurve, DistortionBendsTheCurveAndTheTrueDepthLandsOnTheTruePixel) {
  const Camera cam = Distorted();
  const Rigid3d b_from_a(Eigen::Quaterniond(Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitY())), Eigen::Vector3d(-1, 0.3, 0));
  const Eigen::Vector2d px(150, 100);
  const Eigen::Vector3d x_a = *cam.CamFromImg(px) * 7.0;  // a point 7 m along the ray
  const auto curve = EpipolarCurve(cam, px, cam, b_from_a, {7.0});
  ASSERT_EQ(curve.size(), 2u);
  ASSERT_TRUE(curve[0]);
  EXPECT_NEAR((*curve[0] - *cam.ImgFromCam(b_from_a * x_a)).norm(), 0.0, 1e-9);
  // Three points of the curve are not collinear: the lens bends it.
  const auto dense = EpipolarCurve(cam, px, cam, b_from_a, EpipolarDepths(1.5, 50, 3));
  ASSERT_TRUE(dense[0] && dense[1] && dense[2]);
  const Eigen::Vector2d u = *dense[1] - *dense[0], v = *dense[2] - *dense[0];
  EXPECT_GT(std::abs(u.x() * v.y() - u.y() * v.x()) / (u.norm() * v.norm()), 1e-3);
}

TEST(EpipolarCurve, APixelWithoutARayGivesNoCurve) {
  EXPECT_TRUE(EpipolarCurve(Fisheye(), {-0.5, -0.5}, Pinhole(), Rigid3d(), {1.0}).empty());
}

TEST(AlignToTruth, PlacesAUnitScaleEstimateOverTheTruth) {
  Rig truth;
  const Camera cam = Pinhole();
  // Camera 0 is not the rig frame in the truth; the estimate's gauge is camera 0.
  const Rigid3d cam0_from_rig(Eigen::Quaterniond(Eigen::AngleAxisd(0.1, Eigen::Vector3d::UnitY())), Eigen::Vector3d(0.1, 0, 0));
  const Rigid3d cam1_from_rig(Eigen::Quaterniond(Eigen::AngleAxisd(-0.6, Eigen::Vector3d::UnitY())), Eigen::Vector3d(-0.4, 0, 0.1));
  truth.cameras = {{"cam0", cam, cam0_from_rig, 0.0}, {"cam1", cam, cam1_from_rig, 0.0}};
  FramesFile frames;
  const Rigid3d rig_from_world(Eigen::Quaterniond(Eigen::AngleAxisd(0.4, Eigen::Vector3d::UnitX())), Eigen::Vector3d(1, 2, 3));
  frames.frames = {{"000000", rig_from_world, 0.0}};
  // The estimate: camera 0 the rig frame, unit scale (|centre of cam1| = 1).
  const Rigid3d true_c1_from_c0 = cam1_from_rig * cam0_from_rig.Inverse();
  const double length = true_c1_from_c0.SourceOriginInTarget().norm();
  RigCalibrationResult result;
  result.rig = truth;
  result.rig.cameras[0].cam_from_rig = Rigid3d();
  result.rig.cameras[1].cam_from_rig = Rigid3d(true_c1_from_c0.rotation, true_c1_from_c0.translation / length);
  result.cam_from_rig_rotation = {Eigen::Quaterniond::Identity(), true_c1_from_c0.rotation};
  const AlignedEstimate a = AlignToTruth(result, truth, frames);
  EXPECT_NEAR(a.scale, length, 1e-9);
  ASSERT_TRUE(a.cam_from_cam0[1]);
  EXPECT_NEAR((a.cam_from_cam0[1]->translation - true_c1_from_c0.translation).norm(), 0.0, 1e-9);
  // Camera 0's centre of the estimate's world lands on the true camera 0 at frame 0.
  const Eigen::Vector3d true_cam0_centre = (cam0_from_rig * rig_from_world).SourceOriginInTarget();
  EXPECT_NEAR((a.ToWorld(Eigen::Vector3d::Zero()) - true_cam0_centre).norm(), 0.0, 1e-9);
  // And camera 1's estimated centre (unit scale) on the true camera 1.
  const Eigen::Vector3d est_c1 = result.rig.cameras[1].cam_from_rig->SourceOriginInTarget();
  EXPECT_NEAR((a.ToWorld(est_c1) - (cam1_from_rig * rig_from_world).SourceOriginInTarget()).norm(), 0.0, 1e-9);
}

}  // namespace
}  // namespace rigsim
