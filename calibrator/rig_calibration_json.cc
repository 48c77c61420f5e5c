#include "calibrator/rig_calibration.h"

#include <algorithm>
#include <cmath>

#include "evaluation/match_precision.h"
#include "calibrator/intrinsics_refinement.h"
#include "evaluation/verdicts.h"
#include "geometry/json_io.h"

// The rig calibration's JSON (RigCalibrationToJson), the verdicts it carries, and the estimate
// evaluate scores.
namespace rigsim {

RigEstimate RigEstimateOf(const RigCalibrationResult& r) {
  RigEstimate e;
  e.method = r.semantic_mode;
  e.metric = r.metric_scale;
  for (size_t c = 0; c < r.rig.cameras.size(); ++c) {
    e.cam_from_rig.push_back(r.rig.cameras[c].cam_from_rig);
    const bool rotation_only = !r.rig.cameras[c].cam_from_rig && c < r.cam_from_rig_rotation.size();
    e.rotation_only.push_back(rotation_only ? r.cam_from_rig_rotation[c] : std::nullopt);
  }
  return e;
}

std::optional<bool> CameraWithinTolerance(const RigCalibrationResult& r, size_t c) {
  if (!r.evaluated) return std::nullopt;
  const RigCameraStats& s = r.camera_stats[c];
  if (!s.rotation_error_deg) return false;  // no estimate
  return WithinTolerance(s.rotation_error_deg, s.translation_direction_error_deg, kCameraTolerance);
}

nlohmann::json RigCalibrationToJson(const std::vector<RigCalibrationResult>& results) {
  std::vector<CalibrationReport> reports;
  for (const RigCalibrationResult& r : results) reports.push_back(r.pairwise);
  const nlohmann::json pairwise = ReportToJson(reports);
  nlohmann::json methods = nlohmann::json::object();
  for (const RigCalibrationResult& r : results) {
    nlohmann::json cams = nlohmann::json::array();
    int calibrated = 0, within = 0, calibrated_outside = 0;
    std::optional<double> max_rot, max_dir;  // worst over the cameras that have the error; none: null
    for (size_t c = 0; c < r.rig.cameras.size(); ++c) {
      const auto& pose = r.rig.cameras[c].cam_from_rig;
      const RigCameraStats& s = r.camera_stats[c];
      calibrated += pose.has_value();
      if (s.rotation_error_deg) max_rot = std::max(max_rot.value_or(0.0), *s.rotation_error_deg);
      if (s.translation_direction_error_deg) max_dir = std::max(max_dir.value_or(0.0), *s.translation_direction_error_deg);
      nlohmann::json j;
      j["name"] = r.rig.cameras[c].name;
      j["status"] = r.camera_status[c];
      j["calibrated"] = pose.has_value();
      j["position_known"] = pose.has_value();
      const auto& rq = c < r.cam_from_rig_rotation.size() ? r.cam_from_rig_rotation[c] : std::nullopt;
      j["rotation_wxyz"] = rq ? nlohmann::json({rq->w(), rq->x(), rq->y(), rq->z()}) : nlohmann::json(nullptr);
      j["cam_from_rig"] = pose ? json_io::PoseToJson(*pose) : nlohmann::json(nullptr);
      if (pose) {
        const Eigen::Vector3d centre = pose->SourceOriginInTarget();
        j["centre_in_rig"] = {centre.x(), centre.y(), centre.z()};
      } else {
        j["centre_in_rig"] = nullptr;
      }
      j["observations"] = s.observations;
      j["direction_std_deg"] = json_io::OptionalNumber(s.direction_std_deg);
      j["rotation_error_deg"] = json_io::OptionalNumber(s.rotation_error_deg);
      j["translation_direction_error_deg"] = json_io::OptionalNumber(s.translation_direction_error_deg);
      j["position_error_m"] = json_io::OptionalNumber(s.position_error_m);
      j["intrinsics"] = s.intrinsics ? RefinedIntrinsicsToJson(*s.intrinsics, r.rig.cameras[c].camera) : nlohmann::json(nullptr);
      const std::optional<bool> ok = CameraWithinTolerance(r, c);
      j["within_tolerance"] = ok ? nlohmann::json(*ok) : nlohmann::json(nullptr);
      within += ok.value_or(false);
      calibrated_outside += pose.has_value() && !ok.value_or(true);
      cams.push_back(j);
    }
    nlohmann::json edges = nlohmann::json::array();
    for (const RigEdgeStats& e : r.edges) {
      edges.push_back({{"cam_a", e.cam_a},
                       {"cam_b", e.cam_b},
                       {"inliers", e.inliers},
                       {"used", e.used},
                       {"rotation_only", e.rotation_only},
                       {"rotation_outlier", e.rotation_outlier},
                       {"rotation_residual_deg", json_io::OptionalNumber(e.rotation_residual_deg)},
                       {"rotation_disagreement_deg", json_io::OptionalNumber(e.rotation_disagreement_deg)},
                       {"direction_disagreement_deg", json_io::OptionalNumber(e.direction_disagreement_deg)},
                       {"rejected", e.rejected},
                       {"status", e.status}});
    }
    nlohmann::json summary = {{"cameras", r.rig.cameras.size()},
                              {"cameras_calibrated", calibrated},
                              {"metric_scale", r.metric_scale},
                              {"scale", r.scale},
                              {"reprojection_rms_px", r.reprojection_rms_px},
                              {"initial_reprojection_rms_px", r.initial_reprojection_rms_px},
                              {"tracks", r.num_tracks},
                              {"conflicting_tracks", r.num_conflicting_tracks},
                              {"points", r.num_points},
                              {"observations", r.num_observations},
                              {"filtered_observations", r.num_filtered_observations},
                              {"rotation_outliers", r.num_rotation_outliers},
                              {"frames", r.num_frames},
                              {"frames_posed", r.num_frames_posed},
                              {"rig_motion_estimated", r.rig_motion_estimated},
                              {"temporal_pairs_used", r.num_temporal_pairs_used},
                              {"position_eigenvalue_ratio", std::isfinite(r.position_eigenvalue_ratio)
                                                                ? nlohmann::json(r.position_eigenvalue_ratio)
                                                                : nlohmann::json(nullptr)}};
    summary["tolerance"] = {{"rotation_deg", kCameraTolerance.rotation_deg},
                            {"direction_deg", kCameraTolerance.direction_deg}};
    summary["cameras_within_tolerance"] = r.evaluated ? nlohmann::json(within) : nlohmann::json(nullptr);
    summary["cameras_calibrated_outside_tolerance"] =
        r.evaluated ? nlohmann::json(calibrated_outside) : nlohmann::json(nullptr);
    summary["max_rotation_error_deg"] = json_io::OptionalNumber(r.evaluated ? max_rot : std::nullopt);
    summary["max_translation_direction_error_deg"] = json_io::OptionalNumber(r.evaluated ? max_dir : std::nullopt);
    nlohmann::json m;
    m["summary"] = summary;
    m["timing"] = {{"detect_time_s", r.pairwise.detect_time_s},
                   {"match_time_s", r.pairwise.match_time_s},
                   {"pose_time_s", r.pairwise.pose_time_s},
                   {"temporal_match_time_s", r.pairwise.temporal_match_time_s},
                   {"temporal_pose_time_s", r.pairwise.temporal_pose_time_s},
                   {"rotation_averaging_time_s", r.rotation_averaging_time_s},
                   {"positions_time_s", r.positions_time_s},
                   {"tracks_time_s", r.tracks_time_s},
                   {"bundle_adjustment_time_s", r.bundle_adjustment_time_s}};
    m["cameras"] = cams;
    nlohmann::json frames = nlohmann::json::array();  // per frame index: the rig's pose, or null
    for (const auto& p : r.rig_from_world) frames.push_back(p ? json_io::PoseToJson(*p) : nlohmann::json(nullptr));
    m["rig_from_world_per_frame"] = frames;
    m["edges"] = edges;
    nlohmann::json starts = nlohmann::json::array();
    for (const RigStartSummary& st : r.position_starts) {
      nlohmann::json diffs = nlohmann::json::array();
      for (const auto& d : st.direction_difference_deg) diffs.push_back(json_io::OptionalNumber(d));
      starts.push_back({{"source", st.source},
                        {"cost_px2", st.cost},
                        {"observations", st.observations},
                        {"chosen", st.chosen},
                        {"direction_difference_deg", diffs}});
    }
    m["position_starts"] = starts;
    m["warnings"] = r.warnings;
    const std::string key = r.semantic_mode.empty() ? "rig" : r.semantic_mode;
    // Results of EstimateRig alone have no pairwise report.
    m["pairwise"] = !r.pairwise.pairs.empty() && pairwise["methods"].contains(r.pairwise.semantic_mode)
                        ? pairwise["methods"][r.pairwise.semantic_mode]
                        : nlohmann::json(nullptr);
    methods[key] = m;
  }
  return {{"methods", methods}};
}

}  // namespace rigsim
