#include "geometry/camera.h"

#include <cmath>

#include <Eigen/LU>
#include <numbers>
#include <sstream>
#include <stdexcept>

namespace rigsim {
namespace {

constexpr double kPi = std::numbers::pi;

// Forward-mode dual number with two derivative components: enough to get exact Jacobians of the
// templated distortion functions for Newton's method.
struct Dual {
  double v = 0, d0 = 0, d1 = 0;
  Dual() = default;
  Dual(double value) : v(value) {}  // NOLINT: constants in the templates are written T(1)
  Dual(double value, double a, double b) : v(value), d0(a), d1(b) {}
};
Dual operator+(const Dual& a, const Dual& b) { return {a.v + b.v, a.d0 + b.d0, a.d1 + b.d1}; }
Dual operator*(const Dual& a, const Dual& b) { return {a.v * b.v, a.d0 * b.v + a.v * b.d0, a.d1 * b.v + a.v * b.d1}; }
Dual operator/(const Dual& a, const Dual& b) {
  const double inv = 1.0 / b.v;
  return {a.v * inv, (a.d0 - a.v * inv * b.d0) * inv, (a.d1 - a.v * inv * b.d1) * inv};
}

// Radial part of a perspective model's distortion: distorted radius for undistorted radius r
// (on the u axis, where tangential terms do not enter the radius to first order).
template <typename T>
T DistortedRadius(CameraModelId id, const double* dist, const T& r) {
  T ud, vd;
  const bool full = id == CameraModelId::kFullOpenCV;
  const T zero_tangential[8] = {T(dist[0]), T(dist[1]), T(0.0), T(0.0),
                                T(full ? dist[4] : 0.0), T(full ? dist[5] : 0.0),
                                T(full ? dist[6] : 0.0), T(full ? dist[7] : 0.0)};
  DistortNormalized(id, zero_tangential, r, T(0.0), &ud, &vd);
  return ud;
}

// Finds x in [0, x_max] with f(x) = target for a function increasing on [0, x_max], by Newton's
// method (exact derivative from dual numbers) safeguarded by bisection. `f` is generic in the
// scalar type. Assumes f(0) = 0 <= target <= f(x_max).
template <typename F>
double SolveMonotonic(F f, double target, double x_max) {
  double lo = 0.0, hi = x_max;
  double x = std::min(target, x_max);
  for (int i = 0; i < 100; ++i) {
    const Dual fx = f(Dual(x, 1.0, 0.0));
    const double r = fx.v - target;
    if (r == 0.0) return x;
    if (r > 0) hi = x; else lo = x;
    double next = fx.d0 > 0 ? x - r / fx.d0 : 0.5 * (lo + hi);
    if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
    if (std::abs(next - x) <= 1e-16 * std::max(1.0, x)) return next;
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

namespace {

// Newton's method on the full distortion (tangential terms included) from `x`, with the exact
// Jacobian. Returns the undistorted point when the residual is below `tolerance_px`.
std::optional<Eigen::Vector2d> NewtonUndistort(CameraModelId model, const double* params, const Eigen::Vector2d& distorted,
                                               Eigen::Vector2d x) {
  const double* dist = params + 4;
  Dual dual_dist[8];
  for (int i = 0; i < CameraModelNumParams(model) - 4; ++i) dual_dist[i] = Dual(dist[i]);
  for (int it = 0; it < 30; ++it) {
    Dual ud, vd;
    DistortNormalized(model, dual_dist, Dual(x.x(), 1, 0), Dual(x.y(), 0, 1), &ud, &vd);
    const Eigen::Vector2d f(ud.v - distorted.x(), vd.v - distorted.y());
    Eigen::Matrix2d jac;
    jac << ud.d0, ud.d1, vd.d0, vd.d1;
    const double det = jac.determinant();
    if (!(std::abs(det) > 1e-300)) return std::nullopt;
    const Eigen::Vector2d step = jac.inverse() * f;
    if (!step.allFinite()) return std::nullopt;
    x -= step;
    if (step.norm() <= 1e-15 * std::max(1.0, x.norm())) break;
  }
  Eigen::Vector2d d;
  DistortNormalized(model, dist, x.x(), x.y(), &d.x(), &d.y());
  const double err_px = ((d - distorted).array() * Eigen::Array2d(params[0], params[1])).matrix().norm();
  if (!(err_px < 1e-9)) return std::nullopt;
  return x;
}

}  // namespace

std::optional<Eigen::Vector2d> Camera::UndistortPerspective(const Eigen::Vector2d& distorted) const {
  const double* dist = params_.data() + 4;
  if (model_ == CameraModelId::kPinhole) return distorted;
  const double rd = distorted.norm();
  const double rd_max = DistortedRadius(model_, dist, max_radius_);
  if (rd > rd_max * 1.05) return std::nullopt;
  auto inside = [&](const std::optional<Eigen::Vector2d>& x) { return x && x->norm() <= max_radius_ * (1 + 1e-9); };
  // Most pixels converge from the distorted point itself; near the lens's fold Newton can jump
  // to the wrong branch, so retry from the radial-only inverse, which lies on the right one.
  std::optional<Eigen::Vector2d> x = NewtonUndistort(model_, params_.data(), distorted, distorted);
  if (inside(x)) return x;
  if (rd > 0) {
    const double r = SolveMonotonic([&](auto v) { return DistortedRadius(model_, dist, v); }, std::min(rd, rd_max),
                                    max_radius_);
    x = NewtonUndistort(model_, params_.data(), distorted, distorted * (r / rd));
    if (inside(x)) return x;
  }
  return std::nullopt;
}

std::optional<Eigen::Vector3d> Camera::CamFromImg(const Eigen::Vector2d& px) const {
  const Eigen::Vector2d distorted((px.x() - cx()) / fx(), (px.y() - cy()) / fy());
  if (IsFisheyeModel(model_)) {
    const double* dist = params_.data() + 4;
    const double theta_d = distorted.norm();
    if (theta_d == 0.0) return Eigen::Vector3d(0, 0, 1);
    if (theta_d > FisheyeDistortedTheta(dist, max_theta_)) return std::nullopt;
    const double theta =
        SolveMonotonic(
        [&](auto t) {
          using T = decltype(t);
          const T k[4] = {T(dist[0]), T(dist[1]), T(dist[2]), T(dist[3])};
          return FisheyeDistortedTheta(k, t);
        },
        theta_d, max_theta_);
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
