#include "geometry/camera.h"

#include <cmath>

#include <Eigen/LU>
#include <numbers>
#include <sstream>
#include <stdexcept>

namespace rigsim {
namespace {

constexpr double kPi = std::numbers::pi;

// Radial part of a perspective model's distortion: distorted radius for undistorted radius r
// (on the u axis, where tangential terms do not enter the radius to first order).
double DistortedRadius(CameraModelId id, const double* dist, double r) {
  double ud, vd;
  const double zero_tangential[8] = {dist[0], dist[1], 0.0, 0.0,
                                     id == CameraModelId::kFullOpenCV ? dist[4] : 0.0,
                                     id == CameraModelId::kFullOpenCV ? dist[5] : 0.0,
                                     id == CameraModelId::kFullOpenCV ? dist[6] : 0.0,
                                     id == CameraModelId::kFullOpenCV ? dist[7] : 0.0};
  DistortNormalized(id, id == CameraModelId::kPinhole ? dist : zero_tangential, r, 0.0, &ud, &vd);
  return ud;
}

// Finds x in [0, x_max] with f(x) = target for increasing f, by bisection polished with
// secant steps. Assumes f(0) = 0 <= target <= f(x_max).
template <typename F>
double SolveMonotonic(F f, double target, double x_max) {
  double lo = 0.0, hi = x_max;
  double x = std::min(target, x_max);
  for (int i = 0; i < 200; ++i) {
    const double fx = f(x) - target;
    if (fx == 0.0) return x;
    if (fx > 0) hi = x; else lo = x;
    const double h = 1e-7 * std::max(1.0, x);
    const double d = (f(x + h) - f(x - h)) / (2 * h);
    double next = (d > 0) ? x - fx / d : 0.5 * (lo + hi);
    if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
    if (std::abs(next - x) < 1e-16 * std::max(1.0, x)) return next;
    x = next;
  }
  return x;
}

}  // namespace

Camera::Camera(CameraModelId model, int width, int height, std::vector<double> params)
    : model_(model), width_(width), height_(height), params_(std::move(params)) {
  Check();
  max_radius_ = ComputeMaxUndistortedRadius();
  max_theta_ = IsFisheyeModel(model_) ? max_radius_ : std::atan(max_radius_);
}

Camera Camera::PinholeFromHorizontalFov(int width, int height, double hfov_deg) {
  const double f = 0.5 * width / std::tan(0.5 * hfov_deg * kPi / 180.0);
  return Camera(CameraModelId::kPinhole, width, height, {f, f, 0.5 * (width - 1), 0.5 * (height - 1)});
}

void Camera::Check() const {
  std::ostringstream why;
  const int expected = CameraModelNumParams(model_);
  if (width_ <= 0 || height_ <= 0) {
    why << "image size " << width_ << "x" << height_ << " is not positive";
  } else if (static_cast<int>(params_.size()) != expected) {
    why << CameraModelName(model_) << " takes " << expected << " parameters (" << CameraModelParamNames(model_)
        << "), got " << params_.size();
  } else {
    for (double p : params_) {
      if (!std::isfinite(p)) {
        why << "parameters must be finite";
        break;
      }
    }
    if (why.str().empty() && (params_[0] <= 0 || params_[1] <= 0)) {
      why << "focal lengths must be positive (fx=" << params_[0] << ", fy=" << params_[1] << ")";
    }
  }
  if (!why.str().empty()) throw std::invalid_argument("invalid camera: " + why.str());
}

double Camera::ComputeMaxUndistortedRadius() const {
  const double* dist = params_.data() + 4;
  if (IsFisheyeModel(model_)) {
    // theta_d(theta) must increase; theta itself cannot exceed pi.
    const int steps = 20000;
    double prev = 0.0;
    for (int i = 1; i <= steps; ++i) {
      const double theta = kPi * i / steps;
      const double td = FisheyeDistortedTheta(dist, theta);
      if (!(td > prev)) return kPi * (i - 1) / steps;
      prev = td;
    }
    return kPi;
  }
  if (model_ == CameraModelId::kPinhole) return 1e6;
  // Perspective: scan the normalised radius up to tan(89.4 deg).
  const double r_cap = 100.0;
  const int steps = 100000;
  double prev = 0.0;
  for (int i = 1; i <= steps; ++i) {
    const double r = r_cap * i / steps;
    const double rd = DistortedRadius(model_, dist, r);
    if (!std::isfinite(rd) || !(rd > prev)) return r_cap * (i - 1) / steps;
    prev = rd;
  }
  return r_cap;
}

std::optional<Eigen::Vector2d> Camera::ImgFromCam(const Eigen::Vector3d& x_in_cam) const {
  if (IsFisheyeModel(model_)) {
    const double theta = std::atan2(x_in_cam.head<2>().norm(), x_in_cam.z());
    if (theta > max_theta_) return std::nullopt;
  } else {
    if (!(x_in_cam.z() > 0)) return std::nullopt;
    if (x_in_cam.head<2>().norm() > max_radius_ * x_in_cam.z()) return std::nullopt;
  }
  Eigen::Vector2d px;
  if (!rigsim::ImgFromCam(model_, params_.data(), x_in_cam.data(), px.data())) return std::nullopt;
  return px;
}

std::optional<Eigen::Vector2d> Camera::UndistortPerspective(const Eigen::Vector2d& distorted) const {
  const double* dist = params_.data() + 4;
  if (model_ == CameraModelId::kPinhole) return distorted;
  // Radial-only initial guess, then Newton on the full model (with tangential terms).
  const double rd = distorted.norm();
  const double rd_max = DistortedRadius(model_, dist, max_radius_);
  if (rd > rd_max * 1.05) return std::nullopt;
  Eigen::Vector2d x = distorted;
  if (rd > 0) {
    const double r = SolveMonotonic([&](double v) { return DistortedRadius(model_, dist, v); },
                                    std::min(rd, rd_max), max_radius_);
    x = distorted * (r / rd);
  }
  auto residual = [&](const Eigen::Vector2d& p) {
    Eigen::Vector2d d;
    DistortNormalized(model_, dist, p.x(), p.y(), &d.x(), &d.y());
    return Eigen::Vector2d(d - distorted);
  };
  for (int it = 0; it < 100; ++it) {
    const Eigen::Vector2d f = residual(x);
    if (f.norm() < 1e-16) break;
    Eigen::Matrix2d jac;
    const double h = 1e-7 * std::max(1.0, x.norm());
    for (int c = 0; c < 2; ++c) {
      Eigen::Vector2d dp = Eigen::Vector2d::Zero();
      dp[c] = h;
      jac.col(c) = (residual(x + dp) - residual(x - dp)) / (2 * h);
    }
    const Eigen::Vector2d step = jac.inverse() * f;
    if (!step.allFinite()) return std::nullopt;
    x -= step;
    if (step.norm() < 1e-17 * std::max(1.0, x.norm())) break;
  }
  // Accept only a true inverse inside the monotonic region.
  const double err_px = (residual(x).array() * Eigen::Array2d(params_[0], params_[1])).matrix().norm();
  if (!(err_px < 1e-9) || x.norm() > max_radius_ * (1 + 1e-9)) return std::nullopt;
  return x;
}

std::optional<Eigen::Vector3d> Camera::CamFromImg(const Eigen::Vector2d& px) const {
  const Eigen::Vector2d distorted((px.x() - cx()) / fx(), (px.y() - cy()) / fy());
  if (IsFisheyeModel(model_)) {
    const double* dist = params_.data() + 4;
    const double theta_d = distorted.norm();
    if (theta_d == 0.0) return Eigen::Vector3d(0, 0, 1);
    if (theta_d > FisheyeDistortedTheta(dist, max_theta_)) return std::nullopt;
    const double theta =
        SolveMonotonic([&](double t) { return FisheyeDistortedTheta(dist, t); }, theta_d, max_theta_);
    const Eigen::Vector2d dir = distorted / theta_d;
    return Eigen::Vector3d(std::sin(theta) * dir.x(), std::sin(theta) * dir.y(), std::cos(theta));
  }
  const auto undistorted = UndistortPerspective(distorted);
  if (!undistorted) return std::nullopt;
  return Eigen::Vector3d(undistorted->x(), undistorted->y(), 1.0).normalized();
}

bool Camera::IsInImage(const Eigen::Vector2d& px) const {
  return px.x() >= -0.5 && px.y() >= -0.5 && px.x() < width_ - 0.5 && px.y() < height_ - 0.5;
}

}  // namespace rigsim
