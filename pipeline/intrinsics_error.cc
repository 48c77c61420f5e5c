#include "pipeline/intrinsics_error.h"

#include <cmath>
#include <numbers>
#include <stdexcept>
#include <vector>

#include "common/format.h"
#include "common/splitmix64.h"

namespace rigsim {
namespace {

// Keeps these draws apart from every other stream seeded by the same number (a sweep cell's seed
// also seeds the scene, the placement, the photometric errors and the label noise).
constexpr uint64_t kIntrinsicsErrorSalt = 0x1A7B1C5E5EEDull;

}  // namespace

void IntrinsicsErrorOptions::Check(const std::string& option) const {
  if (!std::isfinite(error) || error < 0 || error > kMaxError) {
    throw std::invalid_argument(option + ": must be 0 to " + Fixed(kMaxError, 1) + ", a fraction (0.01 is 1 %) (got " +
                                Fixed(error, 3) + ")");
  }
}

double IntrinsicsErrorDraw(uint64_t seed, int camera_index, int param) {
  const uint64_t bits = SplitMix64(SplitMix64(SplitMix64(seed ^ kIntrinsicsErrorSalt) ^ uint64_t(uint32_t(camera_index))) ^
                                   uint64_t(uint32_t(param)));
  // Box-Muller on two 32-bit uniforms; u1 in (0, 1) keeps the logarithm finite.
  const double u1 = (double(bits >> 32) + 0.5) / 4294967296.0;
  const double u2 = double(bits & 0xFFFFFFFFull) / 4294967296.0;
  return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * std::numbers::pi * u2);
}

Camera WithIntrinsicsError(const Camera& camera, const IntrinsicsErrorOptions& options, int camera_index) {
  options.Check();
  if (!options.Enabled()) return camera;
  const double e = options.error;
  const auto z = [&](int param) { return IntrinsicsErrorDraw(options.seed, camera_index, param); };
  std::vector<double> p = camera.params();
  const double focal = std::exp(e * z(0));
  p[0] *= focal;
  p[1] *= focal;
  p[2] += e * 0.5 * camera.width() * z(2);
  p[3] += e * 0.5 * camera.height() * z(3);
  for (size_t k = 4; k < p.size(); ++k) p[k] *= 1.0 + e * z(int(k));
  return Camera(camera.model(), camera.width(), camera.height(), std::move(p));
}

Rig WithIntrinsicsError(const Rig& rig, const IntrinsicsErrorOptions& options) {
  options.Check();
  if (!options.Enabled()) return rig;
  Rig out = rig;
  for (size_t c = 0; c < out.cameras.size(); ++c) {
    out.cameras[c].camera = WithIntrinsicsError(rig.cameras[c].camera, options, int(c));
  }
  return out;
}

std::string IntrinsicsErrorMeaning() {
  return "each camera's focal lengths are multiplied by exp(E z), its principal point moved by E z times half the "
         "image's width and height (px), each distortion coefficient multiplied by 1 + E z, every z a standard normal "
         "draw of (seed, camera index, parameter)";
}

}  // namespace rigsim
