#include "geometry/camera_validation.h"

#include <algorithm>
#include <cstdio>
#include <stdexcept>

namespace rigsim {
namespace {

// Border samples per side at most, and interior grid lines per axis.
constexpr int kMaxBorderSamples = 4096;
constexpr int kGridLines = 33;

std::string Px(double x, double y) {
  char buf[64];
  std::snprintf(buf, sizeof(buf), "(%.1f, %.1f)", x, y);
  return buf;
}

}  // namespace

CameraCoverage MeasureCameraCoverage(const Camera& camera) {
  CameraCoverage cov;
  const double w = camera.width(), h = camera.height();
  auto probe = [&](double x, double y) {
    ++cov.samples;
    if (camera.CamFromImg(Eigen::Vector2d(x, y))) return;
    if (cov.invalid_samples++ == 0) {
      cov.first_invalid_x = x;
      cov.first_invalid_y = y;
    }
  };
  // The image covers [-0.5, w-0.5) x [-0.5, h-0.5) (pixel centres at integers): sample its outline,
  // corners included, at most kMaxBorderSamples points per side.
  const int nx = int(std::min<double>(w, kMaxBorderSamples));
  const int ny = int(std::min<double>(h, kMaxBorderSamples));
  for (int i = 0; i <= nx; ++i) {
    const double x = -0.5 + w * i / nx;
    probe(x, -0.5);
    probe(x, h - 0.5);
  }
  for (int j = 1; j < ny; ++j) {
    const double y = -0.5 + h * j / ny;
    probe(-0.5, y);
    probe(w - 0.5, y);
  }
  for (int j = 1; j < kGridLines; ++j) {
    for (int i = 1; i < kGridLines; ++i) probe(-0.5 + w * i / kGridLines, -0.5 + h * j / kGridLines);
  }
  cov.centre_valid = camera.CamFromImg(Eigen::Vector2d(0.5 * (w - 1), 0.5 * (h - 1))).has_value();
  return cov;
}

std::vector<std::string> CheckCameraCoversImage(const Camera& camera, const std::string& name, const std::string& source) {
  const std::string where = source + ": camera '" + name + "': ";
  const std::string model(CameraModelName(camera.model()));
  const std::string size = std::to_string(camera.width()) + "x" + std::to_string(camera.height());
  if (int64_t(camera.width()) * camera.height() > kMaxCameraPixels) {
    throw std::runtime_error(where + "image size " + size + " exceeds the limit of " +
                             std::to_string(kMaxCameraPixels / 1'000'000) + " megapixels");
  }
  const CameraCoverage cov = MeasureCameraCoverage(camera);
  std::vector<std::string> warnings;
  if (IsFisheyeModel(camera.model())) {
    if (!cov.centre_valid) {
      throw std::runtime_error(where + model + " lens has no ray at the image centre " +
                               Px(0.5 * (camera.width() - 1), 0.5 * (camera.height() - 1)) +
                               ": the principal point or the distortion is impossible");
    }
    if (cov.invalid_samples > 0) {
      char buf[200];
      std::snprintf(buf, sizeof(buf),
                    "%.1f%% of the %s image lies outside the fisheye's valid image circle (%lld of %lld sampled "
                    "pixels, e.g. %s); those pixels render black and are not calibrated",
                    100.0 * double(cov.invalid_samples) / double(cov.samples), size.c_str(),
                    static_cast<long long>(cov.invalid_samples), static_cast<long long>(cov.samples),
                    Px(cov.first_invalid_x, cov.first_invalid_y).c_str());
      warnings.push_back(source + ": camera '" + name + "': " + buf);
    }
    return warnings;
  }
  if (cov.invalid_samples > 0) {
    throw std::runtime_error(where + model + " distortion cannot be inverted over the " + size + " image: pixel " +
                             Px(cov.first_invalid_x, cov.first_invalid_y) + " and " +
                             std::to_string(cov.invalid_samples - 1) + " more of " + std::to_string(cov.samples) +
                             " sampled pixels lie beyond the point where the distortion folds back (max field angle " +
                             std::to_string(int(camera.max_valid_angle() * 180.0 / 3.141592653589793 + 0.5)) +
                             " deg); a perspective lens must image every pixel");
  }
  return warnings;
}

std::vector<std::string> CheckRigCoversImages(const Rig& rig, const std::string& source) {
  std::vector<std::string> warnings;
  for (const RigCamera& rc : rig.cameras) {
    for (std::string& w : CheckCameraCoversImage(rc.camera, rc.name, source)) warnings.push_back(std::move(w));
    // The lens the images are rendered through must cover them as well as the model.
    if (rc.render_lens) {
      for (std::string& w : CheckCameraCoversImage(*rc.render_lens, rc.name + " (render_lens)", source)) {
        warnings.push_back(std::move(w));
      }
    }
  }
  return warnings;
}

}  // namespace rigsim
