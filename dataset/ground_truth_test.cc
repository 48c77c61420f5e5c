#include "dataset/ground_truth.h"

#include <gtest/gtest.h>

namespace rigsim {
namespace {

// Range image of a camera looking at the plane z = depth (in its own frame), with an optional
// occluding square closer to the camera.
ImageF PlaneRange(const Camera& cam, const Rigid3d& cam_from_plane, double plane_z) {
  ImageF range(cam.width(), cam.height(), 1);
  const Rigid3d plane_from_cam = cam_from_plane.Inverse();
  for (int y = 0; y < cam.height(); ++y) {
    for (int x = 0; x < cam.width(); ++x) {
      const Eigen::Vector3d ray_cam = *cam.CamFromImg(Eigen::Vector2d(x, y));
      const Eigen::Vector3d o = plane_from_cam.translation;
      const Eigen::Vector3d d = plane_from_cam.rotation * ray_cam;
      const double t = (plane_z - o.z()) / d.z();
      range.at(x, y) = t > 0 ? static_cast<float>(t) : 0.0f;
    }
  }
  return range;
}

TEST(GroundTruth, TransferMatchesTheTrueProjection) {
  const Camera cam = Camera::PinholeFromHorizontalFov(80, 60, 60.0);
  // B is 0.5 m to the right of A; both look at a wall 4 m ahead.
  const Rigid3d a_from_wall;
  const Rigid3d b_from_a(Eigen::Matrix3d::Identity(), Eigen::Vector3d(-0.5, 0, 0));
  const ImageF range_a = PlaneRange(cam, a_from_wall, 4.0);
  const ImageF range_b = PlaneRange(cam, b_from_a * a_from_wall, 4.0);
  const Eigen::Vector2d px_a(50, 30);
  const auto px_b = TransferPixel(px_a, cam, range_a, cam, range_b, b_from_a);
  ASSERT_TRUE(px_b.has_value());
  // Disparity f * b / z.
  EXPECT_NEAR(px_b->x(), 50 - cam.fx() * 0.5 / 4.0, 1e-3);
  EXPECT_NEAR(px_b->y(), 30, 1e-3);
  // Points that leave B's image do not transfer.
  EXPECT_FALSE(TransferPixel(Eigen::Vector2d(2, 30), cam, range_a, cam, range_b, b_from_a).has_value());
}

TEST(GroundTruth, OccludedPointsDoNotTransfer) {
  const Camera cam = Camera::PinholeFromHorizontalFov(80, 60, 60.0);
  const Rigid3d b_from_a(Eigen::Matrix3d::Identity(), Eigen::Vector3d(-0.5, 0, 0));
  const ImageF range_a = PlaneRange(cam, Rigid3d(), 4.0);
  ImageF range_b = PlaneRange(cam, b_from_a, 4.0);
  // Something in front of B covers its centre.
  for (int y = 20; y < 40; ++y)
    for (int x = 20; x < 60; ++x) range_b.at(x, y) = 1.0f;
  const Eigen::Vector2d px_a(50, 30);
  EXPECT_FALSE(TransferPixel(px_a, cam, range_a, cam, range_b, b_from_a).has_value());
  // No surface (sky) in A: nothing to transfer.
  ImageF sky = range_a;
  sky.at(50, 30) = 0.0f;
  EXPECT_FALSE(TransferPixel(px_a, cam, sky, cam, range_b, b_from_a).has_value());
}

TEST(GroundTruth, CoVisibleFractionOfAShiftedView) {
  const Camera cam = Camera::PinholeFromHorizontalFov(80, 60, 60.0);
  const ImageF range = PlaneRange(cam, Rigid3d(), 4.0);
  EXPECT_NEAR(CoVisibleFraction(cam, range, cam, range, Rigid3d()), 1.0, 1e-12);
  // Shift B sideways by half the visible width at 4 m: about half of A is seen by B.
  const double half_width = 4.0 * std::tan(DegToRad(30.0));
  const Rigid3d b_from_a(Eigen::Matrix3d::Identity(), Eigen::Vector3d(-half_width, 0, 0));
  const ImageF range_b = PlaneRange(cam, b_from_a, 4.0);
  EXPECT_NEAR(CoVisibleFraction(cam, range, cam, range_b, b_from_a), 0.5, 0.03);
}

// Several targets at once, over bands of rows, give what one target over the whole image gives.
TEST(GroundTruth, CountCoVisibleSumsOverBandsAndTargets) {
  const Camera cam = Camera::PinholeFromHorizontalFov(80, 60, 60.0);
  const ImageF range = PlaneRange(cam, Rigid3d(), 4.0);
  const double half_width = 4.0 * std::tan(DegToRad(30.0));
  const Rigid3d half(Eigen::Matrix3d::Identity(), Eigen::Vector3d(-half_width, 0, 0));
  const Rigid3d quarter(Eigen::Matrix3d::Identity(), Eigen::Vector3d(-half_width / 2, 0, 0));
  const ImageF range_half = PlaneRange(cam, half, 4.0), range_quarter = PlaneRange(cam, quarter, 4.0);
  const std::vector<TransferTarget> targets = {{&cam, &range_half, half}, {&cam, &range_quarter, quarter}};
  CoVisibleCounts sum;
  sum.visible.assign(2, 0);
  for (int y = 0; y < range.height; y += 7) {  // bands that do not divide the height
    const CoVisibleCounts band = CountCoVisible(cam, range, targets, y, y + 7);
    sum.surface += band.surface;
    for (int t = 0; t < 2; ++t) sum.visible[t] += band.visible[t];
  }
  EXPECT_EQ(sum.surface, size_t(range.width) * range.height);
  EXPECT_DOUBLE_EQ(double(sum.visible[0]) / sum.surface, CoVisibleFraction(cam, range, cam, range_half, half));
  EXPECT_DOUBLE_EQ(double(sum.visible[1]) / sum.surface, CoVisibleFraction(cam, range, cam, range_quarter, quarter));
  EXPECT_NEAR(double(sum.visible[1]) / sum.surface, 0.75, 0.03);

  // Bearings computed beforehand give the same counts; a list of the wrong size is refused.
  std::vector<Eigen::Vector3f> bearings;
  for (int y = 0; y < range.height; ++y) {
    for (int x = 0; x < range.width; ++x) bearings.push_back(cam.CamFromImg(Eigen::Vector2d(x, y))->normalized().cast<float>());
  }
  const CoVisibleCounts given = CountCoVisible(cam, range, targets, 0, range.height, {}, &bearings);
  EXPECT_EQ(given.surface, sum.surface);
  EXPECT_EQ(given.visible, sum.visible);
  bearings.pop_back();
  EXPECT_THROW(CountCoVisible(cam, range, targets, 0, range.height, {}, &bearings), std::invalid_argument);
}

}  // namespace
}  // namespace rigsim
