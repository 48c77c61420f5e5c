// Our camera models against OpenCV's own implementation: same parameter order, same
// distortion sign, same pixel-centre convention. A second, independent implementation is the
// best check that the renderer's images are ground truth for OpenCV-based tools.
#include <random>

#include <gtest/gtest.h>
#include <opencv2/calib3d.hpp>

#include "geometry/camera.h"

namespace rigsim {
namespace {

std::vector<cv::Point3d> RandomPointsInFront(int n, double spread, int seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-spread, spread);
  std::uniform_real_distribution<double> z(1.0, 10.0);
  std::vector<cv::Point3d> pts;
  for (int i = 0; i < n; ++i) {
    const double d = z(rng);
    pts.emplace_back(u(rng) * d, u(rng) * d, d);
  }
  return pts;
}

void ExpectSameProjection(const Camera& cam, const std::vector<cv::Point3d>& pts, const std::vector<cv::Point2d>& cv_px) {
  for (size_t i = 0; i < pts.size(); ++i) {
    const auto px = cam.ImgFromCam(Eigen::Vector3d(pts[i].x, pts[i].y, pts[i].z));
    ASSERT_TRUE(px.has_value());
    EXPECT_NEAR(px->x(), cv_px[i].x, 1e-7);
    EXPECT_NEAR(px->y(), cv_px[i].y, 1e-7);
  }
}

TEST(OpenCvConvention, PerspectiveModelsMatchProjectPoints) {
  const std::vector<std::vector<double>> params = {
      {500, 510, 319.5, 239.5},
      {400, 405, 322, 236, -0.28, 0.07, 0.001, -0.0008},
      {400, 405, 322, 236, -0.3, 0.09, 0.0005, 0.0007, -0.01, 0.05, 0.01, 0.002}};
  const CameraModelId ids[] = {CameraModelId::kPinhole, CameraModelId::kOpenCV, CameraModelId::kFullOpenCV};
  const auto pts = RandomPointsInFront(200, 0.6, 1);
  for (int m = 0; m < 3; ++m) {
    const Camera cam(ids[m], 640, 480, params[m]);
    const cv::Matx33d K(params[m][0], 0, params[m][2], 0, params[m][1], params[m][3], 0, 0, 1);
    // OpenCV's order: k1 k2 p1 p2 [k3 [k4 k5 k6]], the same as ours after fx fy cx cy.
    std::vector<double> dist(params[m].begin() + 4, params[m].end());
    std::vector<cv::Point2d> cv_px;
    cv::projectPoints(pts, cv::Vec3d(0, 0, 0), cv::Vec3d(0, 0, 0), K, dist, cv_px);
    SCOPED_TRACE(std::string(CameraModelName(ids[m])));
    ExpectSameProjection(cam, pts, cv_px);
  }
}

TEST(OpenCvConvention, FisheyeMatchesCvFisheye) {
  const std::vector<double> p = {300, 302, 319.5, 239.5, 0.02, -0.01, 0.003, -0.0005};
  const Camera cam(CameraModelId::kOpenCVFisheye, 640, 480, p);
  const auto pts = RandomPointsInFront(200, 1.5, 2);
  const cv::Matx33d K(p[0], 0, p[2], 0, p[1], p[3], 0, 0, 1);
  const cv::Vec4d D(p[4], p[5], p[6], p[7]);
  std::vector<cv::Point2d> cv_px;
  cv::fisheye::projectPoints(pts, cv_px, cv::Vec3d(0, 0, 0), cv::Vec3d(0, 0, 0), K, D);
  ExpectSameProjection(cam, pts, cv_px);
}

TEST(OpenCvConvention, UnprojectionAgreesWithUndistortPoints) {
  const std::vector<double> p = {400, 405, 322, 236, -0.28, 0.07, 0.001, -0.0008};
  const Camera cam(CameraModelId::kOpenCV, 640, 480, p);
  const cv::Matx33d K(p[0], 0, p[2], 0, p[1], p[3], 0, 0, 1);
  const std::vector<double> dist(p.begin() + 4, p.end());
  std::vector<cv::Point2d> px = {{10, 10}, {600, 50}, {322, 236}, {100, 400}};
  std::vector<cv::Point2d> normalized;
  // OpenCV's undistortion is iterative and approximate; ours is exact, so compare loosely.
  cv::undistortPoints(px, normalized, K, dist, cv::noArray(), cv::noArray(),
                      cv::TermCriteria(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, 200, 1e-12));
  for (size_t i = 0; i < px.size(); ++i) {
    const Eigen::Vector3d ray = *cam.CamFromImg(Eigen::Vector2d(px[i].x, px[i].y));
    EXPECT_NEAR(ray.x() / ray.z(), normalized[i].x, 1e-6);
    EXPECT_NEAR(ray.y() / ray.z(), normalized[i].y, 1e-6);
  }
}

}  // namespace
}  // namespace rigsim
