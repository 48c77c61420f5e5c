#include "calibrator/intrinsics_refinement.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "geometry/json_io.h"

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

double FocalErrorPercent(const std::vector<double>& estimate, const std::vector<double>& truth) {
  return 100.0 * std::max(std::abs(estimate[0] / truth[0] - 1.0), std::abs(estimate[1] / truth[1] - 1.0));
}

double PrincipalPointErrorPx(const std::vector<double>& estimate, const std::vector<double>& truth) {
  return std::hypot(estimate[2] - truth[2], estimate[3] - truth[3]);
}

void CompareIntrinsicsWithTruth(const Camera& truth, RefinedIntrinsics* r) {
  const std::vector<double>& t = truth.params();
  if (r->refined.size() != t.size() || r->given.size() != t.size()) return;
  r->focal_error_percent = FocalErrorPercent(r->refined, t);
  r->principal_point_error_px = PrincipalPointErrorPx(r->refined, t);
  r->given_focal_error_percent = FocalErrorPercent(r->given, t);
  r->given_principal_point_error_px = PrincipalPointErrorPx(r->given, t);
}

nlohmann::json RefinedIntrinsicsToJson(const RefinedIntrinsics& r, const Camera& camera) {
  nlohmann::json j = {{"model", std::string(CameraModelName(camera.model()))},
                      {"param_names", std::string(CameraModelParamNames(camera.model()))},
                      {"given", r.given},
                      {"refined", r.refined},
                      {"stddev", r.stddev.empty() ? nlohmann::json(nullptr) : nlohmann::json(r.stddev)}};
  if (r.given.size() >= 4 && r.refined.size() >= 4) {
    j["focal_change_percent"] = {100.0 * (r.refined[0] / r.given[0] - 1.0), 100.0 * (r.refined[1] / r.given[1] - 1.0)};
    j["principal_point_change_px"] = {r.refined[2] - r.given[2], r.refined[3] - r.given[3]};
  }
  j["focal_error_percent"] = json_io::OptionalNumber(r.focal_error_percent);
  j["principal_point_error_px"] = json_io::OptionalNumber(r.principal_point_error_px);
  j["given_focal_error_percent"] = json_io::OptionalNumber(r.given_focal_error_percent);
  j["given_principal_point_error_px"] = json_io::OptionalNumber(r.given_principal_point_error_px);
  return j;
}

Rig WithGivenIntrinsics(const Rig& rig, const Rig& intrinsics, const std::string& source) {
  Rig out = rig;
  for (RigCamera& rc : out.cameras) {
    const int i = intrinsics.FindCamera(rc.name);
    if (i < 0) {
      std::string names;
      for (const RigCamera& c : intrinsics.cameras) names += (names.empty() ? "" : ", ") + c.name;
      throw std::invalid_argument(source + ": no camera '" + rc.name + "' (it has " + (names.empty() ? "none" : names) +
                                  "); give the intrinsics of every camera of the dataset");
    }
    const Camera& given = intrinsics.cameras[i].camera;
    if (given.width() != rc.camera.width() || given.height() != rc.camera.height()) {
      throw std::invalid_argument(source + ": camera '" + rc.name + "' is " + std::to_string(given.width()) + "x" +
                                  std::to_string(given.height()) + ", the dataset's photos are " +
                                  std::to_string(rc.camera.width()) + "x" + std::to_string(rc.camera.height()));
    }
    rc.camera = given;
  }
  return out;
}

}  // namespace rigsim
