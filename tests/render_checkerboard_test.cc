// End-to-end check that rendered images are ground truth for every lens: a checkerboard plane at a
// known pose is rendered through each camera model (fisheye beyond 180 degrees included), its
// inner corners are detected with OpenCV (an implementation independent of ours), and the
// detections are compared with Camera::ImgFromCam of the true 3D corners.
//
// Measured (64 spp, 8-bit sRGB output, cv::findChessboardCornersSB then cv::cornerSubPix on the
// linearised image; Debian 12, OpenCV 4.6), detected minus projected corners:
//   PINHOLE 0.031 px RMS / 0.058 max, OPENCV 0.032 / 0.062, FULL_OPENCV 0.032 / 0.057,
//   OPENCV_FISHEYE (220 deg lens, board straddling 90 deg) 0.031 / 0.049.
// The same detector on an independently supersampled ideal image of the pinhole board gives the
// same errors within 0.005 px, so what remains is the detector's own error, not the renderer's.
// The test prints the figures ("[ measured ]") and records them as test properties.
#include <cmath>
#include <cstdio>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Geometry>
#include <gtest/gtest.h>
#include <opencv2/calib3d.hpp>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "geometry/camera.h"
#include "geometry/rigid3.h"
#include "renderer/renderer.h"
#include "scene/scene.h"

namespace rigsim {
namespace {

constexpr double kPi = 3.14159265358979323846;
// The bound on the agreement of detected and projected corners.
constexpr double kMaxRms = 0.05;
// Single corners may be a little worse than the RMS (8-bit quantisation, detector noise).
constexpr double kMaxErr = 0.08;

struct Board {
  int squares_x = 9;  // squares across; inner corners = squares - 1
  int squares_y = 7;
  double square_m = 0.1;
  // Board frame: x along the rows, y down the columns, z = 0 on the board.
  Rigid3d cam_from_board;

  int inner_x() const { return squares_x - 1; }
  int inner_y() const { return squares_y - 1; }
  // Inner corner (i, j), i in 1..squares_x-1, j in 1..squares_y-1, in the camera frame.
  Eigen::Vector3d Corner(int i, int j) const { return cam_from_board * Eigen::Vector3d(i * square_m, j * square_m, 0); }
};

// The board as quads in the camera frame (cam_from_world = identity): checker squares plus a
// one-square white margin (the detectors need a light border), split into a white and a black mesh.
Scene CheckerboardScene(const Board& board) {
  Scene scene;
  scene.source = "checkerboard";
  Material white, black;
  white.name = "white";
  white.base_color_factor = Eigen::Vector4f(0.85f, 0.85f, 0.85f, 1);
  black.name = "black";
  black.base_color_factor = Eigen::Vector4f(0.03f, 0.03f, 0.03f, 1);
  scene.materials = {white, black};
  SceneMesh meshes[2];
  for (int m = 0; m < 2; ++m) {
    meshes[m].name = m == 0 ? "white squares" : "black squares";
    meshes[m].class_id = 20;  // traffic sign: any label will do
    meshes[m].instance_id = 1;
    meshes[m].material = m;
  }
  for (int j = -1; j <= board.squares_y; ++j) {
    for (int i = -1; i <= board.squares_x; ++i) {
      const bool inside = i >= 0 && j >= 0 && i < board.squares_x && j < board.squares_y;
      const int m = inside && (i + j) % 2 == 0 ? 1 : 0;
      SceneMesh& mesh = meshes[m];
      const uint32_t base = uint32_t(mesh.positions.size());
      for (const auto& [di, dj] : {std::pair{0, 0}, {1, 0}, {1, 1}, {0, 1}}) {
        const Eigen::Vector3d p = board.cam_from_board * Eigen::Vector3d((i + di) * board.square_m, (j + dj) * board.square_m, 0);
        mesh.positions.push_back(p.cast<float>());
      }
      for (uint32_t k : {0u, 1u, 2u, 0u, 2u, 3u}) mesh.indices.push_back(base + k);
    }
  }
  scene.meshes = {meshes[0], meshes[1]};
  return scene;
}

// Uniform lighting (no sun, no shadows) so that the only edges are the board's.
RenderOptions CheckerOptions() {
  RenderOptions options;
  options.samples_per_pixel = 64;  // 8 x 8 stratified: edge coverage to ~1/64 of a pixel
  options.sun_intensity = 0.0;
  options.shadows = false;
  options.sky_intensity = 1.0;
  options.seed = 7;
  return options;
}

cv::Mat Gray(const ImageU8& rgb) {
  cv::Mat gray(rgb.height, rgb.width, CV_8UC1);
  for (int y = 0; y < rgb.height; ++y) {
    for (int x = 0; x < rgb.width; ++x) {
      gray.at<uint8_t>(y, x) = uint8_t((int(rgb.at(x, y, 0)) + rgb.at(x, y, 1) + rgb.at(x, y, 2) + 1) / 3);
    }
  }
  return gray;
}

// sRGB-decoded (linear light) and blurred with a Gaussian of sigma 1 px, as float.
cv::Mat LinearBlurred(const cv::Mat& gray8) {
  cv::Mat lut(1, 256, CV_32F);
  for (int i = 0; i < 256; ++i) {
    const float c = i / 255.0f;
    lut.at<float>(i) = c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f);
  }
  cv::Mat linear(gray8.size(), CV_32F), blurred;
  for (int y = 0; y < gray8.rows; ++y) {
    for (int x = 0; x < gray8.cols; ++x) linear.at<float>(y, x) = lut.at<float>(gray8.at<uint8_t>(y, x));
  }
  cv::GaussianBlur(linear, blurred, cv::Size(0, 0), 1.0);
  return blurred;
}

// A board whose centre sits along `centre_dir` (camera frame) at `distance`, facing the camera,
// then turned by `tilt_deg` about its own x and y axes so that the view is oblique.
Rigid3d BoardPoseFacing(const Board& board, const Eigen::Vector3d& centre_dir, double distance, double tilt_x_deg,
                        double tilt_y_deg) {
  const Eigen::Vector3d z = centre_dir.normalized();  // board normal points away from the camera
  Eigen::Vector3d x = Eigen::Vector3d::UnitY().cross(z);
  if (x.norm() < 1e-6) x = Eigen::Vector3d::UnitX();
  x.normalize();
  const Eigen::Vector3d y = z.cross(x);
  Eigen::Matrix3d cam_R_board;
  cam_R_board << x, y, z;
  cam_R_board = cam_R_board * (Eigen::AngleAxisd(DegToRad(tilt_x_deg), Eigen::Vector3d::UnitX()) *
                               Eigen::AngleAxisd(DegToRad(tilt_y_deg), Eigen::Vector3d::UnitY()))
                                  .toRotationMatrix();
  const Eigen::Vector3d half(0.5 * board.squares_x * board.square_m, 0.5 * board.squares_y * board.square_m, 0);
  const Eigen::Vector3d t = distance * z - cam_R_board * half;
  return Rigid3d(cam_R_board, t);
}

struct CornerStats {
  double rms = 0, max = 0;
  int matched = 0;
};

// Renders, detects and compares; fails the test when the board is not found.
CornerStats MeasureCorners(const std::string& name, const Camera& camera, const Board& board) {
  const Scene scene = CheckerboardScene(board);
  const Renderer renderer(scene);
  const RenderedView view = renderer.Render(camera, Rigid3d(), CheckerOptions());
  const cv::Mat gray = Gray(view.rgb);

  // Projections of the true corners; every one must be inside the image and the lens.
  std::vector<Eigen::Vector2d> truth;
  for (int j = 1; j <= board.inner_y(); ++j) {
    for (int i = 1; i <= board.inner_x(); ++i) {
      const std::optional<Eigen::Vector2d> px = camera.ImgFromCam(board.Corner(i, j));
      EXPECT_TRUE(px && camera.IsInImage(*px)) << name << ": test setup: corner " << i << "," << j << " not in view";
      if (!px) return {};
      truth.push_back(*px);
    }
  }

  std::vector<cv::Point2f> corners;
  const bool found = cv::findChessboardCornersSB(gray, cv::Size(board.inner_x(), board.inner_y()), corners,
                                                 cv::CALIB_CB_EXHAUSTIVE | cv::CALIB_CB_ACCURACY);
  EXPECT_TRUE(found) << name << ": the checkerboard was not detected";
  if (!found) return {};
  // Refinement by gradient orthogonality (cv::cornerSubPix) on the linear-light image, lightly
  // blurred. Both steps matter (measured on the pinhole board): cornerSubPix on the 8-bit sRGB
  // image alone leaves 0.07 px RMS, also on an independently supersampled ideal image, because the
  // tone curve moves blurred edges and the 8-bit gradients near the junction are coarse; the
  // renderer averages samples in linear light, so that is the space where edges are unbiased.
  // The window is small (13 x 13) because the detector assumes straight edges: on the fisheye
  // board, whose rows bend strongly near 90 degrees, a 29 x 29 window moved every corner 0.07 px
  // outwards (a bias that grows with the window, so it is the detector's, not the image's).
  cv::cornerSubPix(LinearBlurred(gray), corners, cv::Size(6, 6), cv::Size(-1, -1),
                   cv::TermCriteria(cv::TermCriteria::EPS + cv::TermCriteria::COUNT, 100, 1e-5));

  CornerStats stats;
  double sum2 = 0;
  for (const cv::Point2f& c : corners) {
    // Detection order may be flipped: match each detection to the nearest true corner.
    double best = 1e9;
    for (const Eigen::Vector2d& t : truth) best = std::min(best, (Eigen::Vector2d(c.x, c.y) - t).norm());
    EXPECT_LT(best, 1.0) << name << ": detected corner (" << c.x << ", " << c.y << ") far from every true corner";
    sum2 += best * best;
    stats.max = std::max(stats.max, best);
    ++stats.matched;
  }
  EXPECT_EQ(stats.matched, int(truth.size())) << name;
  stats.rms = std::sqrt(sum2 / std::max(1, stats.matched));
  std::printf("[ measured ] %-15s %2d corners  rms %.4f px  max %.4f px\n", name.c_str(), stats.matched, stats.rms,
              stats.max);
  ::testing::Test::RecordProperty(name + "_rms_px", std::to_string(stats.rms));
  ::testing::Test::RecordProperty(name + "_max_px", std::to_string(stats.max));
  return stats;
}

void ExpectAccurate(const CornerStats& s, const std::string& name) {
  EXPECT_LT(s.rms, kMaxRms) << name;
  EXPECT_LT(s.max, kMaxErr) << name;
}

TEST(RenderCheckerboardTest, Pinhole) {
  const Camera camera(CameraModelId::kPinhole, 640, 480, {520, 515, 322.3, 237.8});
  Board board;
  board.cam_from_board = BoardPoseFacing(board, Eigen::Vector3d(0.1, -0.05, 1), 1.6, 15, -25);
  ExpectAccurate(MeasureCorners("PINHOLE", camera, board), "PINHOLE");
}

TEST(RenderCheckerboardTest, OpenCV) {
  const Camera camera(CameraModelId::kOpenCV, 640, 480, {430, 432, 318.6, 241.2, -0.28, 0.07, 0.001, -0.0008});
  Board board;
  // Off-centre, where the barrel distortion bends the rows visibly.
  board.cam_from_board = BoardPoseFacing(board, Eigen::Vector3d(0.45, 0.2, 1), 1.4, -10, 20);
  ExpectAccurate(MeasureCorners("OPENCV", camera, board), "OPENCV");
}

TEST(RenderCheckerboardTest, FullOpenCV) {
  const Camera camera(CameraModelId::kFullOpenCV, 640, 480,
                      {400, 405, 322, 236, -0.3, 0.09, 0.0005, 0.0007, -0.01, 0.05, 0.01, 0.002});
  Board board;
  board.cam_from_board = BoardPoseFacing(board, Eigen::Vector3d(-0.4, -0.25, 1), 1.3, 20, 10);
  ExpectAccurate(MeasureCorners("FULL_OPENCV", camera, board), "FULL_OPENCV");
}

// Kannala-Brandt lens with a 220-degree field of view; the board straddles the 90-degree plane,
// so half of its corners lie behind the camera's image plane (z < 0).
TEST(RenderCheckerboardTest, FisheyeBeyond180Degrees) {
  const Camera camera(CameraModelId::kOpenCVFisheye, 800, 800, {190, 191, 401.2, 398.7, 0.02, -0.004, 0.0005, -0.0001});
  ASSERT_GT(camera.max_valid_angle(), DegToRad(110));
  Board board;
  board.squares_x = 7;
  board.squares_y = 5;
  board.square_m = 0.16;
  const double theta = DegToRad(90), phi = DegToRad(30);
  const Eigen::Vector3d dir(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta));
  board.cam_from_board = BoardPoseFacing(board, dir, 0.9, 0, 0);
  int behind = 0;
  for (int j = 1; j <= board.inner_y(); ++j) {
    for (int i = 1; i <= board.inner_x(); ++i) behind += board.Corner(i, j).z() < 0;
  }
  ASSERT_GT(behind, 5) << "test setup: the board should reach beyond 90 degrees";
  ExpectAccurate(MeasureCorners("OPENCV_FISHEYE", camera, board), "OPENCV_FISHEYE");
}

// A fisheye whose image circle lies inside the sensor: every pixel outside the circle is void in
// every output (label 0, instance 0, range 0, RGB black), every pixel inside sees the enclosing box.
TEST(RenderCheckerboardTest, FisheyeImageCircleInsideTheSensor) {
  // theta_d = theta (1 - 0.05 theta^2) stops increasing at theta ~ 2.58 rad (148 deg): image circle
  // radius 110 * 1.72 = 189 px inside a 420 x 420 sensor.
  const Camera camera(CameraModelId::kOpenCVFisheye, 420, 420, {110, 110, 209.5, 209.5, -0.05, 0, 0, 0});
  ASSERT_GT(camera.max_valid_angle(), kPi / 2);
  ASSERT_LT(camera.max_valid_angle(), kPi);
  Scene scene;
  scene.source = "box";
  SceneMesh box;
  box.name = "box";
  box.class_id = 11;  // building
  box.instance_id = 3;
  const float s = 5.0f;
  for (int corner = 0; corner < 8; ++corner) {
    box.positions.emplace_back(corner & 1 ? s : -s, corner & 2 ? s : -s, corner & 4 ? s : -s);
  }
  box.indices = {0, 1, 3, 0, 3, 2, 4, 6, 7, 4, 7, 5, 0, 4, 5, 0, 5, 1, 2, 3, 7, 2, 7, 6, 0, 2, 6, 0, 6, 4, 1, 5, 7, 1, 7, 3};
  scene.meshes.push_back(box);
  RenderOptions options;
  options.samples_per_pixel = 4;
  // Off-centre and turned so that no pixel's ray runs exactly along a box edge.
  const Rigid3d cam_from_world(Eigen::Quaterniond(Eigen::AngleAxisd(0.3, Eigen::Vector3d(0.2, 1, 0.1).normalized())),
                               Eigen::Vector3d(0.31, -0.17, 0.45));
  const RenderedView view = Renderer(scene).Render(camera, cam_from_world, options);
  int invalid = 0, valid = 0;
  for (int y = 0; y < camera.height(); ++y) {
    for (int x = 0; x < camera.width(); ++x) {
      if (camera.CamFromImg(Eigen::Vector2d(x, y))) {
        ++valid;
        ASSERT_EQ(view.label.at(x, y), 11) << x << "," << y;
        ASSERT_EQ(view.instance.at(x, y), 3) << x << "," << y;
        ASSERT_GT(view.range.at(x, y), 0.0f) << x << "," << y;
        continue;
      }
      ++invalid;
      ASSERT_EQ(view.label.at(x, y), 0) << x << "," << y;
      ASSERT_EQ(view.instance.at(x, y), 0) << x << "," << y;
      ASSERT_EQ(view.range.at(x, y), 0.0f) << x << "," << y;
      for (int c = 0; c < 3; ++c) ASSERT_EQ(view.rgb.at(x, y, c), 0) << x << "," << y;
    }
  }
  // The four sensor corners are outside the circle, the centre inside.
  EXPECT_EQ(view.label.at(0, 0), 0);
  EXPECT_EQ(view.label.at(419, 419), 0);
  EXPECT_EQ(view.label.at(209, 209), 11);
  // The circle (radius ~189 px) covers about pi * 189^2 / 420^2 = 64% of the sensor.
  EXPECT_NEAR(double(valid) / (valid + invalid), kPi * 189.0 * 189.0 / (420.0 * 420.0), 0.03);
}

}  // namespace
}  // namespace rigsim
