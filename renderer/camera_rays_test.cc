// Rays through the camera model, seen in rendered labels: boundaries land on the pixels the lens
// model projects them to (pinhole, strong distortion, a rotated pose), pixels outside the lens are
// empty, and the cached pixel-centre bearings are the model's own.
#include <algorithm>
#include <array>
#include <memory>
#include <vector>

#include <gtest/gtest.h>

#include "labels/cityscapes.h"
#include "renderer/camera_rays.h"
#include "renderer/render_test_scenes.h"
#include "renderer/renderer.h"

namespace rigsim {
namespace {

TEST(CameraRaysTest, LabelBoundaryFallsOnTheRightPixelsPinhole) {
  const Camera camera = SmallPinhole();
  const double d = 4.0;
  // Edges at fractional pixel positions, off-centre in x and y, so that a half-pixel shift or a
  // flipped axis moves whole rows or columns across the boundary.
  auto world_x = [&](double u) { return float((u - camera.cx()) / camera.fx() * d); };
  auto world_y = [&](double v) { return float((v - camera.cy()) / camera.fy() * d); };
  Scene scene;
  AddFrontQuad(scene, world_x(20.3), world_x(45.8), world_y(10.7), world_y(30.2), float(d), kCar, 3);
  const RenderedView view = Renderer(scene).Render(camera, Rigid3d(), Opts());

  const auto top_left = camera.ImgFromCam(Eigen::Vector3d(world_x(20.3), world_y(10.7), d));
  const auto bottom_right = camera.ImgFromCam(Eigen::Vector3d(world_x(45.8), world_y(30.2), d));
  ASSERT_TRUE(top_left && bottom_right);
  int inside_count = 0;
  for (int y = 0; y < 48; ++y) {
    for (int x = 0; x < 64; ++x) {
      const bool inside = x > top_left->x() && x < bottom_right->x() && y > top_left->y() && y < bottom_right->y();
      inside_count += inside;
      ASSERT_EQ(view.label.at(x, y), inside ? kCar : kSkyId) << x << "," << y;
      ASSERT_EQ(view.instance.at(x, y), inside ? 3 : 0);
    }
  }
  EXPECT_EQ(inside_count, (45 - 21 + 1) * (30 - 11 + 1));
}

// For points along the quad's edges projected with ImgFromCam, the pixel just inside the
// projected edge has the quad's label and the pixel just outside has not.
void ExpectEdgesProjectWhereTheyShould(const Camera& camera, const std::array<Eigen::Vector3d, 4>& corners,
                                       const RenderedView& view) {
  const Eigen::Vector3d centre = 0.25 * (corners[0] + corners[1] + corners[2] + corners[3]);
  int checked = 0;
  for (int e = 0; e < 4; ++e) {
    const Eigen::Vector3d a = corners[e], b = corners[(e + 1) % 4];
    for (int i = 1; i < 40; ++i) {
      const Eigen::Vector3d p = a + (b - a) * (i / 40.0);
      const auto px = camera.ImgFromCam(p);
      const auto along = camera.ImgFromCam(p + (b - a) * 1e-4);
      const auto towards_centre = camera.ImgFromCam(p + (centre - p) * 1e-4);
      ASSERT_TRUE(px && along && towards_centre);
      const Eigen::Vector2d tangent = (*along - *px).normalized();
      Eigen::Vector2d inward(-tangent.y(), tangent.x());
      if (inward.dot(*towards_centre - *px) < 0) inward = -inward;
      // 0.9 px off the edge: the nearest pixel centre is then >= 0.19 px on the correct side.
      const Eigen::Vector2d in = (*px + 0.9 * inward).array().round();
      const Eigen::Vector2d out = (*px - 0.9 * inward).array().round();
      if (!camera.IsInImage(in) || !camera.IsInImage(out)) continue;
      EXPECT_EQ(view.label.at(int(in.x()), int(in.y())), kCar) << "edge " << e << " sample " << i << " at " << px->transpose();
      EXPECT_EQ(view.label.at(int(out.x()), int(out.y())), kSkyId) << "edge " << e << " sample " << i << " at " << px->transpose();
      ++checked;
    }
  }
  EXPECT_GT(checked, 100);
}

TEST(CameraRaysTest, LabelBoundaryFollowsTheLensDistortion) {
  // Strong barrel distortion: edges move by several pixels against a pinhole, so a wrong sign
  // or an image-space approximation fails.
  const Camera camera(CameraModelId::kOpenCV, 64, 48, {60, 60, 31.5, 23.5, -0.3, 0, 0, 0});
  const double d = 4.0;
  const std::array<Eigen::Vector3d, 4> corners = {Eigen::Vector3d(-0.42 * d, -0.33 * d, d), Eigen::Vector3d(0.45 * d, -0.33 * d, d),
                                                  Eigen::Vector3d(0.45 * d, 0.3 * d, d), Eigen::Vector3d(-0.42 * d, 0.3 * d, d)};
  Scene scene;
  AddQuad(scene, corners[0].cast<float>(), corners[1].cast<float>(), corners[2].cast<float>(),
          corners[3].cast<float>(), kCar, 1);
  const Renderer renderer(scene);
  ExpectEdgesProjectWhereTheyShould(camera, corners, renderer.Render(camera, Rigid3d(), Opts()));

  // The pinhole check above also passes for an undistorted camera; make sure the distortion
  // actually moved the edges (the test would not catch a missing distortion otherwise).
  const Camera pinhole(CameraModelId::kPinhole, 64, 48, {60, 60, 31.5, 23.5});
  const Eigen::Vector2d corner_distorted = *camera.ImgFromCam(corners[1]);
  const Eigen::Vector2d corner_pinhole = *pinhole.ImgFromCam(corners[1]);
  EXPECT_GT((corner_distorted - corner_pinhole).norm(), 2.0);
  const RenderedView undistorted = renderer.Render(pinhole, Rigid3d(), Opts());
  const RenderedView distorted = renderer.Render(camera, Rigid3d(), Opts());
  EXPECT_NE(undistorted.label.data, distorted.label.data);
}

TEST(CameraRaysTest, LabelBoundaryWithARotatedPose) {
  // Camera 2 m to the right and turned: exercises cam_from_world (rotation conjugate, centre).
  const Camera camera(CameraModelId::kOpenCV, 64, 48, {55, 55, 31.5, 23.5, -0.1, 0.01, 0, 0});
  const Eigen::Matrix3d r = Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitY()).toRotationMatrix() *
                            Eigen::AngleAxisd(-0.1, Eigen::Vector3d::UnitX()).toRotationMatrix();
  const Rigid3d world_from_cam(r, Eigen::Vector3d(2.0, 0.5, -1.0));
  const Rigid3d cam_from_world = world_from_cam.Inverse();
  std::array<Eigen::Vector3d, 4> corners_in_cam = {Eigen::Vector3d(-1.2, -0.9, 5), Eigen::Vector3d(1.4, -1.0, 5.5),
                                                   Eigen::Vector3d(1.3, 1.1, 6), Eigen::Vector3d(-1.0, 0.8, 5.5)};
  // Make it planar: project the 4th corner onto the plane of the first three.
  const Eigen::Vector3d n = (corners_in_cam[1] - corners_in_cam[0]).cross(corners_in_cam[2] - corners_in_cam[0]).normalized();
  corners_in_cam[3] -= n * n.dot(corners_in_cam[3] - corners_in_cam[0]);
  std::array<Eigen::Vector3d, 4> corners_in_world;
  for (int i = 0; i < 4; ++i) corners_in_world[i] = world_from_cam * corners_in_cam[i];
  Scene scene;
  AddQuad(scene, corners_in_world[0].cast<float>(), corners_in_world[1].cast<float>(),
          corners_in_world[2].cast<float>(), corners_in_world[3].cast<float>(), kCar, 1);
  const RenderedView view = Renderer(scene).Render(camera, cam_from_world, Opts());
  ExpectEdgesProjectWhereTheyShould(camera, corners_in_cam, view);
}

TEST(CameraRaysTest, PixelsOutsideTheLensValidRegionAreEmpty) {
  // k1 = -0.3 at this focal length folds back before the image corners: those pixels have no ray.
  const Camera camera(CameraModelId::kOpenCV, 64, 48, {40, 40, 31.5, 23.5, -0.3, 0, 0, 0});
  Scene scene;
  AddFrontQuad(scene, -100, 100, -100, 100, 3, kRoad, 2);
  const RenderedView view = Renderer(scene).Render(camera, Rigid3d(), Opts());
  int invalid = 0;
  for (int y = 0; y < 48; ++y) {
    for (int x = 0; x < 64; ++x) {
      const bool valid = camera.CamFromImg(Eigen::Vector2d(x, y)).has_value();
      if (valid) {
        ASSERT_EQ(view.label.at(x, y), kRoad);
        ASSERT_GT(view.range.at(x, y), 0);
        continue;
      }
      ++invalid;
      ASSERT_EQ(view.label.at(x, y), 0);
      ASSERT_EQ(view.instance.at(x, y), 0);
      ASSERT_EQ(view.range.at(x, y), 0.0f);
      for (int c = 0; c < 3; ++c) ASSERT_EQ(view.rgb.at(x, y, c), 0);
    }
  }
  EXPECT_GT(invalid, 0);
  EXPECT_LT(invalid, 64 * 48 / 2);
}

// The pixel-centre bearings Render traces: CamFromImg's, normalised, and zero outside the lens.
TEST(CameraRaysTest, PixelCentreBearingsAreTheCameraModelsRays) {
  const Camera fisheye(CameraModelId::kOpenCVFisheye, 64, 48, {12, 12, 31.5, 23.5, 0.05, -0.01, 0, 0});
  const Scene empty;
  const std::shared_ptr<const std::vector<Eigen::Vector3f>> kept = Renderer(empty).PixelCentreBearings(fisheye);
  const std::vector<Eigen::Vector3f>& bearings = *kept;  // outlives the renderer: the pointer keeps it
  ASSERT_EQ(bearings.size(), size_t(64 * 48));
  int outside = 0;
  for (int y = 0; y < 48; ++y) {
    for (int x = 0; x < 64; ++x) {
      const Eigen::Vector3f& b = bearings[size_t(y) * 64 + x];
      const auto ray = fisheye.CamFromImg(Eigen::Vector2d(x, y));
      if (!ray) {
        EXPECT_TRUE(b.isZero()) << x << ", " << y;
        ++outside;
        continue;
      }
      EXPECT_LT((b.cast<double>() - ray->normalized()).norm(), 1e-6) << x << ", " << y;
    }
  }
  EXPECT_GT(outside, 0);  // the corners lie beyond the lens's valid image circle
}

}  // namespace
}  // namespace rigsim

namespace rigsim {
namespace {

TEST(CameraRaysTest, SampleBearingsInterpolatedBetweenPixelCentresAreTheCameraModelsRays) {
  const std::vector<Camera> cameras = {
      Camera(CameraModelId::kPinhole, 160, 120, {100, 100, 79.5, 59.5}),
      Camera(CameraModelId::kOpenCV, 160, 120, {80, 80, 79.5, 59.5, -0.25, 0.06, 0.001, -0.002}),
      Camera(CameraModelId::kOpenCVFisheye, 160, 120, {40, 40, 79.5, 59.5, 0.05, -0.01, 0.002, -0.0005})};
  PixelCentreRayCache cache;
  for (const Camera& camera : cameras) {
    const PixelCentreRays& centres = *cache.For(camera);
    double worst = 0;
    int exact = 0;
    const bool fisheye = camera.model() == CameraModelId::kOpenCVFisheye;
    for (double y = -0.49; y < 119.5; y += 0.73) {
      for (double x = -0.49; x < 159.5; x += 0.61) {
        const auto expected = camera.CamFromImg({x, y});
        const auto got = SampleBearing(camera, centres, {x, y});
        ASSERT_EQ(expected.has_value(), got.has_value()) << x << "," << y;
        if (!got) continue;
        const double error = (got->cast<double>() - expected->normalized()).norm();
        worst = std::max(worst, error);
        exact += *got == expected->normalized().cast<float>();
      }
    }
    if (fisheye) {
      EXPECT_LT(worst, 1e-7);  // computed exactly (in float)
    } else {
      EXPECT_LT(worst * camera.fx(), 0.005) << CameraModelName(camera.model());  // in pixels
      EXPECT_GT(exact, 100);  // the image's border: computed exactly
    }
  }
}

}  // namespace
}  // namespace rigsim
