// A calibrated camera: model, parameters, image size, and the lens's valid field of view.
// See camera_models.h for the frame, pixel and parameter conventions.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "geometry/camera_models.h"

namespace rigsim {

class Camera {
 public:
  Camera() = default;
  // Validates the parameters (Check) and precomputes the lens's valid field of view.
  // Throws std::invalid_argument with the reason when they are impossible.
  Camera(CameraModelId model, int width, int height, std::vector<double> params);

  // Pinhole camera with the principal point at the image centre and the given horizontal FOV.
  static Camera PinholeFromHorizontalFov(int width, int height, double hfov_deg);

  CameraModelId model() const { return model_; }
  int width() const { return width_; }
  int height() const { return height_; }
  const std::vector<double>& params() const { return params_; }
  double fx() const { return params_[0]; }
  double fy() const { return params_[1]; }
  double cx() const { return params_[2]; }
  double cy() const { return params_[3]; }

  // Pixel of a point in the camera frame, or nullopt when the point lies outside the lens's
  // valid field of view (behind a perspective camera, or where the distortion polynomial stops
  // being monotonic). The pixel may lie outside the image: see IsInImage.
  std::optional<Eigen::Vector2d> ImgFromCam(const Eigen::Vector3d& x_in_cam) const;

  // Unit bearing (camera frame) of a pixel, inverting the distortion numerically to far below
  // 1e-9 px; nullopt when the pixel lies outside the lens's valid image region.
  std::optional<Eigen::Vector3d> CamFromImg(const Eigen::Vector2d& px) const;

  // True for pixel coordinates inside the image rectangle [-0.5, w-0.5) x [-0.5, h-0.5).
  bool IsInImage(const Eigen::Vector2d& px) const;

  // Largest angle from the optical axis that the lens images validly (radians; may exceed pi/2
  // for fisheye lenses).
  double max_valid_angle() const { return max_theta_; }

  // Same model, size and parameters (what follows from them is equal then too).
  bool operator==(const Camera&) const = default;

 private:
  void Check() const;
  // Undistorted normalised radius (perspective) or theta (fisheye) where the radial
  // distortion stops increasing monotonically, capped by the model's own limit.
  double ComputeMaxUndistortedRadius() const;
  std::optional<Eigen::Vector2d> UndistortPerspective(const Eigen::Vector2d& distorted) const;

  CameraModelId model_ = CameraModelId::kPinhole;
  int width_ = 0;
  int height_ = 0;
  std::vector<double> params_;
  double max_radius_ = 0.0;  // normalised radius (perspective) or theta (fisheye)
  double max_theta_ = 0.0;
};

}  // namespace rigsim
