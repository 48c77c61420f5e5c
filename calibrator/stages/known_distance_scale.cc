#include "calibrator/stages/known_distance_scale.h"

#include <algorithm>

#include "common/format.h"

namespace rigsim {

namespace {
constexpr const char* kKnownDistanceIgnored = "known distance ignored: ";
}  // namespace

std::string MetricScale::Warning() const { return kKnownDistanceIgnored + why_not; }

void DropKnownDistanceWarning(RigCalibrationResult* result) { DropWarnings(result, kKnownDistanceIgnored); }

MetricScale ScaleToKnownDistance(const RigObservations& obs, const KnownDistance& known,
                                 PerCamera<Rigid3d>* cam_from_rig, PerFrame<Rigid3d>* rig_from_world) {
  const auto [a, b] = KnownDistanceCameras(known, obs.camera_names, "EstimateRig");
  const auto& pose = *cam_from_rig;
  MetricScale out;
  if (!pose[a] || !pose[b]) {
    out.why_not = obs.camera_names[pose[a] ? b : a] + " has no position, so the result has no metric scale";
    return out;
  }
  const double d = (pose[a]->SourceOriginInTarget() - pose[b]->SourceOriginInTarget()).norm();
  if (!(d > 1e-12)) {
    out.why_not = "the two cameras' estimated centres coincide";
    return out;
  }
  out.factor = known.metres / d;
  ScaleTranslations(out.factor, cam_from_rig, rig_from_world);
  out.scale = "metric: |" + obs.camera_names[a] + " - " + obs.camera_names[b] + "| = " + Fixed(known.metres, 4) + " m";
  return out;
}

}  // namespace rigsim
