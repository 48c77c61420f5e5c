#include "rigs/lens_residual.h"

#include <algorithm>
#include <cstdio>
#include <limits>
#include <cmath>
#include <numbers>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include <Eigen/Cholesky>
#include <Eigen/Core>

#include "common/splitmix64.h"
#include "rigs/rng.h"

namespace rigsim {
namespace {

// The grid the model is fitted on: this many pixels across, and as many down as keep them square.
constexpr int kFitColumns = 25;

std::string Px(double v) {
  char s[32];
  std::snprintf(s, sizeof s, "%g", v);
  return s;
}

// The image's four corner pixels (their centres).
std::vector<Eigen::Vector2d> Corners(const Camera& c) {
  const double w = c.width() - 1, h = c.height() - 1;
  return {{0, 0}, {w, 0}, {0, h}, {w, h}};
}

// A grid of pixels over the whole image, its corners included, and their rays through `lens`.
struct FitSamples {
  std::vector<Eigen::Vector2d> px;
  std::vector<Eigen::Vector3d> rays;
};
FitSamples SampleLens(const Camera& lens) {
  const int rows = std::max(5, int(std::lround(kFitColumns * double(lens.height()) / lens.width())));
  FitSamples s;
  for (int j = 0; j < rows; ++j) {
    for (int i = 0; i < kFitColumns; ++i) {
      const Eigen::Vector2d px((lens.width() - 1) * double(i) / (kFitColumns - 1), (lens.height() - 1) * double(j) / (rows - 1));
      const auto ray = lens.CamFromImg(px);
      if (!ray) {
        throw std::invalid_argument("the lens folds over inside the image (pixel (" + Px(px.x()) + ", " + Px(px.y()) +
                                    ") has no ray)");
      }
      s.px.push_back(px);
      s.rays.push_back(*ray);
    }
  }
  return s;
}

// Pixel distances of the model with `params` from the samples, x and y for each.
Eigen::VectorXd Residuals(CameraModelId model, const Eigen::VectorXd& params, const FitSamples& s) {
  Eigen::VectorXd r(2 * s.px.size());
  for (size_t i = 0; i < s.px.size(); ++i) {
    double px[2];
    if (!ImgFromCam(model, params.data(), s.rays[i].data(), px)) {
      px[0] = px[1] = 1e6;  // behind the camera: far off, so the fit moves away from it
    }
    r[2 * i] = px[0] - s.px[i].x();
    r[2 * i + 1] = px[1] - s.px[i].y();
  }
  return r;
}

// The lens of `camera` with its extra terms scaled by `a` along the drawn direction.
Camera MakeLens(const Camera& camera, double a, double mix) {
  std::vector<double> p(12, 0.0);
  const std::vector<double>& m = camera.params();
  std::copy(m.begin(), m.end(), p.begin());  // PINHOLE's 4 or OPENCV's 8: FULL_OPENCV's first ones
  if (camera.model() == CameraModelId::kPinhole) {
    p[4] = a * std::cos(mix);
    p[5] = a * std::sin(mix);
  } else {
    p[8] = a * mix;
  }
  return Camera(CameraModelId::kFullOpenCV, camera.width(), camera.height(), std::move(p));
}

}  // namespace

void LensResidualOptions::Check() const {
  if (!std::isfinite(corner_px) || corner_px < 0 || corner_px > kMaxCornerPx) {
    throw std::invalid_argument("lens residual: " + Px(corner_px) + " px is outside 0 to " + Px(kMaxCornerPx) +
                                " px (the model's miss at the image corners)");
  }
}

double CornerResidualPx(const Camera& model, const Camera& lens) {
  double worst = 0.0;
  for (const Eigen::Vector2d& corner : Corners(lens)) {
    const auto ray = lens.CamFromImg(corner);
    const auto px = ray ? model.ImgFromCam(*ray) : std::nullopt;
    if (!px) {
      throw std::invalid_argument("the lens or its model folds over before the corner pixel (" + Px(corner.x()) + ", " +
                                  Px(corner.y()) + ")");
    }
    worst = std::max(worst, (*px - corner).norm());
  }
  return worst;
}

Camera FitModelToLens(const Camera& start, const Camera& lens) {
  const FitSamples s = SampleLens(lens);
  const CameraModelId model = start.model();
  Eigen::VectorXd p = Eigen::Map<const Eigen::VectorXd>(start.params().data(), Eigen::Index(start.params().size()));
  const Eigen::Index n = p.size();
  Eigen::VectorXd r = Residuals(model, p, s);
  double cost = r.squaredNorm();
  double lambda = 1e-6;
  // Levenberg-Marquardt with central-difference derivatives: a few parameters, smooth in all of them.
  bool converged = false;
  for (int iteration = 0; iteration < 50 && !converged; ++iteration) {
    Eigen::MatrixXd J(r.size(), n);
    for (Eigen::Index k = 0; k < n; ++k) {
      const double h = 1e-6 * std::max(1.0, std::abs(p[k]));
      Eigen::VectorXd plus = p, minus = p;
      plus[k] += h;
      minus[k] -= h;
      J.col(k) = (Residuals(model, plus, s) - Residuals(model, minus, s)) / (2 * h);
    }
    const Eigen::MatrixXd JtJ = J.transpose() * J;
    const Eigen::VectorXd g = J.transpose() * r;
    bool improved = false;
    for (int tries = 0; tries < 10 && !improved; ++tries) {
      Eigen::MatrixXd A = JtJ;
      A.diagonal() += lambda * JtJ.diagonal();
      const Eigen::VectorXd step = A.ldlt().solve(-g);
      const Eigen::VectorXd next = p + step;
      const Eigen::VectorXd r_next = Residuals(model, next, s);
      if (r_next.squaredNorm() < cost) {
        improved = true;
        const double gain = cost - r_next.squaredNorm();
        p = next;
        r = r_next;
        cost = r.squaredNorm();
        lambda = std::max(1e-12, lambda * 0.1);
        converged = gain <= 1e-15 * std::max(1.0, cost);
      } else {
        lambda *= 10;
      }
    }
    if (!improved) break;
  }
  return Camera(model, start.width(), start.height(), std::vector<double>(p.data(), p.data() + n));
}

LensAndModel DrawLensResidual(const Camera& camera, double corner_px, uint64_t seed) {
  if (camera.model() != CameraModelId::kPinhole && camera.model() != CameraModelId::kOpenCV) {
    throw std::invalid_argument("a lens richer than its model is drawn for PINHOLE and OPENCV cameras only (this one is " +
                                std::string(CameraModelName(camera.model())) + ")");
  }
  if (!(corner_px > 0)) throw std::invalid_argument("the lens residual must be > 0 px, got " + Px(corner_px));
  Rng rng(seed);
  const bool pinhole = camera.model() == CameraModelId::kPinhole;
  // PINHOLE: k1 and k2 mixed by an angle; OPENCV: k3 barrel (-1) or pincushion (+1) at the rim.
  const double mix = pinhole ? 2 * std::numbers::pi * rng.Uniform() : (rng.Uniform() < 0.5 ? -1.0 : 1.0);
  // A first guess from the size of the term at the corner (the fit then takes some of it up).
  const std::optional<Eigen::Vector3d> corner_ray = camera.CamFromImg(Eigen::Vector2d(0, 0));
  if (!corner_ray || !(corner_ray->z() > 0)) {
    throw std::invalid_argument("its model folds over inside the image (pixel (0, 0) has no ray)");
  }
  const double rc = corner_ray->head<2>().norm() / corner_ray->z();
  double a = corner_px / (camera.fx() * std::pow(rc, pinhole ? 3 : 7));
  // The residual grows as a power of the extra terms' size (about linearly while they are small):
  // secant steps in log-log coordinates from a slope of 1, kept inside the bracket of sizes that
  // fall short (lo) and that overshoot or fold the lens over at the corners (hi).
  double lo = 0, hi = std::numeric_limits<double>::infinity();
  double previous_log_a = 0, previous_log_residual = 0, slope = 1.0;
  bool have_previous = false;
  std::string why = "the lens folds over inside the image";
  for (int iteration = 0; iteration < 60; ++iteration) {
    LensAndModel out{Camera(), Camera()};
    double residual = 0;
    try {
      out.lens = MakeLens(camera, a, mix);
      out.model = FitModelToLens(camera, out.lens);
      residual = CornerResidualPx(out.model, out.lens);
    } catch (const std::invalid_argument& e) {
      why = e.what();
      hi = a;
      a = lo > 0 ? std::sqrt(lo * hi) : 0.5 * a;
      continue;
    }
    if (std::abs(residual - corner_px) <= 1e-3 * corner_px) return out;
    (residual < corner_px ? lo : hi) = a;
    const double log_a = std::log(a), log_residual = std::log(residual);
    if (have_previous && log_a != previous_log_a) {
      slope = std::clamp((log_residual - previous_log_residual) / (log_a - previous_log_a), 0.25, 4.0);
    }
    previous_log_a = log_a;
    previous_log_residual = log_residual;
    have_previous = true;
    a *= std::pow(corner_px / residual, 1.0 / slope);
    if (!(a > lo && a < hi)) a = std::isfinite(hi) ? (lo > 0 ? std::sqrt(lo * hi) : 0.5 * hi) : 2 * lo;
  }
  throw std::invalid_argument("a lens whose model misses it by " + Px(corner_px) + " px at the corners is out of reach (" +
                              why + "); ask for a smaller residual");
}

void ApplyLensResidual(Rig& rig, const LensResidualOptions& options) {
  options.Check();
  if (!options.Enabled()) return;
  for (size_t i = 0; i < rig.cameras.size(); ++i) {
    RigCamera& c = rig.cameras[i];
    if (c.render_lens) {
      throw std::invalid_argument("lens residual: camera '" + c.name + "' already has a render_lens (from its rig file)");
    }
    try {
      LensAndModel drawn = DrawLensResidual(c.camera, options.corner_px, SplitMix64(options.seed ^ SplitMix64(i + 1)));
      c.camera = std::move(drawn.model);
      c.render_lens = std::move(drawn.lens);
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument("lens residual: camera '" + c.name + "': " + e.what());
    }
  }
}

}  // namespace rigsim
