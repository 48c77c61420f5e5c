#include "calibrator/calibrator_test_support.h"

#include <utility>
#include <vector>

namespace rigsim {

RigObservations ObserveSyntheticRig(SyntheticRig& s, const SyntheticObservationOptions& options) {
  const int cameras = static_cast<int>(s.rig.cameras.size());
  const int frames = static_cast<int>(s.rig_from_world.size());
  RigObservations obs;
  for (const RigCamera& rc : s.rig.cameras) {
    obs.camera_names.push_back(rc.name);
    obs.cameras.push_back(rc.camera);
  }
  obs.keypoints = s.keypoints;
  for (int a = 0; a < cameras; ++a) {
    for (int b = a + 1; b < cameras; ++b) {
      std::vector<std::vector<std::pair<int, int>>> per_frame;
      for (int k = 0; k < frames; ++k) per_frame.push_back(s.CandidateMatches({k, a}, {k, b}));
      auto [estimate, inliers] = EstimatePairFromMatches(obs.cameras, obs.keypoints, a, b, per_frame, options.two_view);
      obs.pairs.push_back(estimate);
      obs.inliers.push_back(std::move(inliers));
      obs.matches.push_back({a, b, std::move(per_frame)});
    }
  }
  for (int c = 0; c < cameras && options.temporal_pairs; ++c) {
    const Camera& camera = obs.cameras[c];
    for (int k = 0; k + 1 < frames; ++k) {
      const std::vector<std::pair<int, int>> m = s.CandidateMatches({k, c}, {k + 1, c});
      std::vector<Eigen::Vector2d> pa, pb;
      for (const auto& [i, j] : m) {
        pa.push_back(s.keypoints[k][c][i]);
        pb.push_back(s.keypoints[k + 1][c][j]);
      }
      const TwoViewResult tv = EstimateRelativePose(camera, pa, camera, pb, options.two_view);
      TemporalPairEstimate t;
      t.camera = c;
      t.frame = k;
      t.two_view = ToEstimate(tv, static_cast<int>(m.size()));
      t.matches = m;
      for (size_t i = 0; i < m.size() && tv.success; ++i) {
        if (tv.inlier_mask[i]) t.inliers.push_back(m[i]);
      }
      obs.temporal.push_back(std::move(t));
    }
  }
  return obs;
}

std::vector<CameraErrors> ErrorsAgainst(const Rig& truth, const RigCalibrationResult& result) {
  RigEstimate e;
  e.metric = result.scale_kind == ScaleKind::kMetric;
  for (size_t c = 0; c < result.rig.cameras.size(); ++c) {
    e.cam_from_rig.push_back(result.rig.cameras[c].cam_from_rig);
    e.rotation_only.push_back(e.cam_from_rig.back() ? std::nullopt : result.cam_from_rig_rotation.at(c));
  }
  return CalibrationCameraErrors(truth, e);
}

}  // namespace rigsim
