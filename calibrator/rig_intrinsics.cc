#include "calibrator/rig_intrinsics.h"

#include <utility>

namespace rigsim {

RigObservations ReestimateWithIntrinsics(const RigObservations& obs, const std::vector<Camera>& cameras,
                                         const TwoViewOptions& options) {
  RigObservations out = obs;
  out.cameras = cameras;
  for (size_t p = 0; p < obs.pairs.size() && p < obs.matches.size(); ++p) {
    const PairMatches& m = obs.matches[p];
    size_t total = 0;
    for (const auto& frame : m.per_frame) total += frame.size();
    if (total == 0) continue;
    auto [estimate, inliers] = EstimatePairFromMatches(cameras, obs.keypoints, m.cam_a, m.cam_b, m.per_frame, options);
    out.pairs[p] = estimate;
    out.inliers[p] = std::move(inliers);
  }
  for (TemporalPairEstimate& t : out.temporal) {
    if (t.matches.empty()) continue;
    const Camera& camera = cameras.at(t.camera);
    std::vector<Eigen::Vector2d> pa, pb;
    for (const auto& [i, j] : t.matches) {
      pa.push_back(obs.keypoints[t.frame][t.camera][i]);
      pb.push_back(obs.keypoints[t.frame + 1][t.camera][j]);
    }
    const TwoViewResult tv = EstimateRelativePose(camera, pa, camera, pb, WithoutRivalSearch(options));
    t.two_view = tv.estimate;
    t.inliers.clear();
    for (size_t i = 0; i < t.matches.size() && tv.estimate.success; ++i) {
      if (tv.inlier_mask[i]) t.inliers.push_back(t.matches[i]);
    }
  }
  return out;
}

RigCalibrationResult EstimateRigAndIntrinsics(const RigObservations& obs, const RigCalibrationOptions& options,
                                              const RigPass& pass) {
  options.Tell("refining the intrinsics: the rig with the given ones first");
  RigCalibrationOptions first = options;
  first.bundle_adjustment.refine_intrinsics = true;
  first.max_rejected_pairs = 0;  // the pairs' poses are off by the given intrinsics' errors
  const RigCalibrationResult rough = pass(obs, first);
  std::vector<Camera> refined = obs.cameras;
  for (size_t c = 0; c < refined.size(); ++c) {
    if (rough.camera_stats[c].intrinsics) refined[c] = rough.rig.cameras[c].camera;
  }
  RigCalibrationOptions second = options;
  second.bundle_adjustment.refine_intrinsics = true;
  second.bundle_adjustment.intrinsics_priors.centres = obs.cameras;
  options.Tell("refining the intrinsics: the pairs and the rig again with the refined ones");
  const RigObservations reestimated = ReestimateWithIntrinsics(obs, refined, options.pairwise.two_view);
  RigCalibrationResult result = pass(reestimated, second);
  for (const PairEstimate& p : reestimated.pairs) result.reestimated_pairs.push_back(p.two_view);
  result.work += rough.work;
  return result;
}

}  // namespace rigsim
