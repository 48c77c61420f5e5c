#include "calibrator/estimators/intrinsics_refinement.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace rigsim {

void IntrinsicsPriorOptions::Check() const {
  auto positive = [](double v, const char* name) {
    if (!(v > 0) || !std::isfinite(v)) throw std::invalid_argument(std::string("IntrinsicsPriorOptions: ") + name + " must be > 0");
  };
  positive(focal_fraction, "focal_fraction");
  positive(aspect_fraction, "aspect_fraction");
  positive(principal_point_fraction, "principal_point_fraction");
  positive(first_radial, "first_radial");
  positive(higher_radial, "higher_radial");
  positive(tangential, "tangential");
  positive(pixel_noise_px, "pixel_noise_px");
}

std::vector<double> IntrinsicsPriorSigmas(const Camera& given, const IntrinsicsPriorOptions& o) {
  const std::vector<double>& p = given.params();
  const double pp = o.principal_point_fraction * std::max(given.width(), given.height());
  std::vector<double> sigma = {o.focal_fraction * std::abs(p[0]), o.focal_fraction * std::abs(p[1]), pp, pp};
  switch (given.model()) {
    case CameraModelId::kPinhole: break;
    case CameraModelId::kOpenCV:  // k1 k2 p1 p2
      sigma.insert(sigma.end(), {o.first_radial, o.higher_radial, o.tangential, o.tangential});
      break;
    case CameraModelId::kFullOpenCV:  // k1 k2 p1 p2 k3 k4 k5 k6
      sigma.insert(sigma.end(), {o.first_radial, o.higher_radial, o.tangential, o.tangential, o.higher_radial,
                                 o.higher_radial, o.higher_radial, o.higher_radial});
      break;
    case CameraModelId::kOpenCVFisheye:  // k1 k2 k3 k4
      sigma.insert(sigma.end(), {o.first_radial, o.higher_radial, o.higher_radial, o.higher_radial});
      break;
  }
  return sigma;
}

Eigen::Vector4d GivenIntrinsicsDeviation::OfCamera(int c, const Camera& camera) const {
  if (!per_camera_px.empty()) return per_camera_px.at(c);
  return {focal_fraction * std::abs(camera.fx()), focal_fraction * std::abs(camera.fy()), principal_point_px,
          principal_point_px};
}

void GivenIntrinsicsDeviation::Check() const {
  auto fail = [](const std::string& why) { throw std::invalid_argument("GivenIntrinsicsDeviation: " + why); };
  // Half the focal length is no calibration; the linearisation would not hold far before it.
  if (!(focal_fraction >= 0 && focal_fraction < 0.5)) fail("focal_fraction must be >= 0 and < 0.5");
  if (!(principal_point_px >= 0) || !std::isfinite(principal_point_px)) fail("principal_point_px must be >= 0");
  for (const Eigen::Vector4d& sd : per_camera_px) {
    if (!sd.allFinite() || (sd.array() < 0).any()) fail("per_camera_px must hold finite values >= 0");
  }
}

}  // namespace rigsim
