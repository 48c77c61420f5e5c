#include "calibrator/stages/stated_deviations.h"

#include "calibrator/estimators/bundle_covariance.h"

namespace rigsim {
namespace {

template <typename T>
const std::optional<T>& Of(const PerCamera<T>& per_camera, int c) {
  static const std::optional<T> none;
  return c >= 0 && c < static_cast<int>(per_camera.size()) ? per_camera[c] : none;
}

}  // namespace

std::optional<double> PlacementDirectionStdDeg(const MultiFrameBundleAdjustmentResult& ba, int c,
                                               const Eigen::Vector3d& centre) {
  const auto& cov = Of(ba.centre_covariance, c);
  if (!cov) return std::nullopt;
  const auto& share = Of(ba.centre_covariance_of_intrinsics, c);
  return PlacementDirectionStdDeg(centre, *cov, share ? &*share : nullptr, ba.residual_correlation);
}

bool HasIntrinsicsShare(const MultiFrameBundleAdjustmentResult& ba, int c) {
  return Of(ba.centre_covariance_of_intrinsics, c).has_value();
}

void SetIntrinsicsShare(const MultiFrameBundleAdjustmentResult& ba, int c, RigCameraStats* stats) {
  stats->direction_intrinsics_std_deg.reset();
  stats->rotation_intrinsics_std_deg.reset();
  const auto& share = Of(ba.centre_covariance_of_intrinsics, c);
  const auto& pose = Of(ba.poses.cam_from_rig, c);
  if (stats->direction_std_deg && share && pose) {
    stats->direction_intrinsics_std_deg = DirectionStdDeg(pose->SourceOriginInTarget(), *share);
  }
  if (stats->rotation_std_deg) stats->rotation_intrinsics_std_deg = Of(ba.rotation_stddev_of_intrinsics_deg, c);
}

}  // namespace rigsim
