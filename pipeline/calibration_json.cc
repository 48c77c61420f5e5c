#include "pipeline/calibration_json.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "evaluation/pose_errors.h"
#include "evaluation/verdicts.h"
#include "geometry/json_io.h"

namespace rigsim {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::json;

Json OptionalInt(const std::optional<int>& v) { return v ? Json(*v) : Json(nullptr); }

// Pose error of a pair for the AUC (verdicts.h): a pair the calibrator does not stand by, or a
// rotation-only estimate of a rig with a baseline, counts as infinite.
double PoseError(const PairResult& pr, const PairAgainstTruth& truth) {
  const bool gt_has_baseline = truth.cam_b_from_cam_a.translation.norm() > 1e-9;
  return PoseErrorDeg(pr.Solved(), truth.rotation_error_deg, truth.translation_direction_error_deg, gt_has_baseline);
}

const PairAgainstTruth* PairTruth(const CalibrationScores* truth, size_t p) {
  return truth && p < truth->pairs.size() ? &truth->pairs[p] : nullptr;
}

const CameraAgainstTruth* CameraTruth(const CalibrationScores* truth, size_t c) {
  return truth && c < truth->cameras.size() ? &truth->cameras[c] : nullptr;
}

double DetectTimeOf(const CalibrationRun& run, size_t m) {
  return m < run.records.size() ? run.records[m].detect_time_s : 0.0;
}

}  // namespace

std::string ScaleText(const RigCalibrationResult& r) {
  return r.scale_kind == ScaleKind::kUnit ? r.scale + " (--known-distance CAM_A CAM_B METRES makes it metric)" : r.scale;
}

Json PairResultToJson(const PairResult& pr, const PairAgainstTruth* truth) {
  const TwoViewEstimate& tv = pr.two_view;
  const PairAgainstTruth none;
  const PairAgainstTruth& t = truth ? *truth : none;
  Json j;
  j["cam_a"] = pr.cam_a;
  j["cam_b"] = pr.cam_b;
  j["success"] = pr.Solved();
  j["rotation_only"] = tv.rotation_only;
  j["pair_type"] = tv.success ? Json(std::string(PairTypeName(tv.pair_type))) : Json(nullptr);
  j["failure_reason"] = pr.Solved() ? std::string() : PairStatus(pr);
  j["frames"] = pr.frames;
  j["matches"] = tv.num_matches;
  j["inliers"] = tv.num_inliers;
  j["homography_inliers"] = tv.num_homography_inliers;
  if (tv.rival) {
    j["rival_pose"] = {{"direction_deg", tv.rival->direction_deg},
                       {"rotation_deg", tv.rival->rotation_deg},
                       {"inliers", tv.rival->inliers},
                       {"rival_closer", tv.rival->rival_closer},
                       {"pose_closer", tv.rival->pose_closer}};
  } else {
    j["rival_pose"] = nullptr;
  }
  j["inlier_ratio"] = tv.num_matches > 0 ? Json(double(tv.num_inliers) / tv.num_matches) : Json(nullptr);
  j["median_residual_deg"] = tv.success ? Json(tv.median_residual_deg) : Json(nullptr);
  // Which way the baseline points: of the inliers with parallax enough to tell, how many lie in
  // front of both cameras under the pose and under the best of the other three.
  j["cheirality"] = {{"points", tv.cheirality_points},
                     {"in_front", tv.points_in_front},
                     {"in_front_otherwise", tv.points_in_front_otherwise}};
  j["rotation_error_deg"] = json_io::OptionalNumber(t.rotation_error_deg);
  j["translation_direction_error_deg"] = json_io::OptionalNumber(t.translation_direction_error_deg);
  const std::optional<bool> within = PairWithinTolerance(pr, truth);
  j["within_tolerance"] = within ? Json(*within) : Json(nullptr);
  j["match_precision"] = json_io::OptionalNumber(t.match_precision);
  j["matches_evaluated"] = t.matches_evaluated;
  j["matches_correct"] = t.matches_correct;
  j["matches_at_infinity"] = t.matches_at_infinity;
  j["cross_class_matches"] = OptionalInt(t.cross_class_matches);
  j["cross_class_wrong"] =
      t.cross_class_matches ? Json(*t.cross_class_matches - t.cross_class_correct) : Json(nullptr);
  j["inlier_precision"] = json_io::OptionalNumber(t.inlier_precision);
  j["inliers_evaluated"] = t.inliers_evaluated;
  j["inliers_correct"] = t.inliers_correct;
  j["distance_evaluations"] = pr.distance_evaluations;
  j["match_time_s"] = pr.match_time_s;
  j["pose_time_s"] = pr.pose_time_s;
  j["cam_b_from_cam_a"] = tv.success ? json_io::PoseToJson(tv.cam_b_from_cam_a) : Json(nullptr);
  return j;
}

Json PairwiseReportJson(const CalibrationReport& rep, const CalibrationScores* truth, double detect_time_s) {
  Json pairs = Json::array();
  std::vector<double> pose_errors, rotation_errors;
  int succeeded = 0, rotation_only = 0, planar = 0, within = 0, succeeded_outside = 0;
  int64_t matches = 0, inliers = 0;
  const PooledMatchPrecision pooled = truth ? PoolMatchPrecision(*truth) : PooledMatchPrecision{};
  for (size_t p = 0; p < rep.pairs.size(); ++p) {
    const PairResult& pr = rep.pairs[p];
    const PairAgainstTruth* t = PairTruth(truth, p);
    pairs.push_back(PairResultToJson(pr, t));
    succeeded += pr.Solved();
    rotation_only += pr.two_view.rotation_only;
    planar += pr.two_view.success && pr.two_view.pair_type == PairType::kPlanar;
    matches += pr.two_view.num_matches;
    inliers += pr.two_view.num_inliers;
    if (!t) continue;
    const bool ok = PairWithinTolerance(pr, t).value_or(false);
    within += ok;
    succeeded_outside += pr.Solved() && !ok;
    pose_errors.push_back(PoseError(pr, *t));
    rotation_errors.push_back(t->rotation_error_deg.value_or(std::numeric_limits<double>::infinity()));
  }
  const bool has_truth = truth != nullptr && !rep.pairs.empty();
  Json summary;
  summary["pairs"] = rep.pairs.size();
  summary["pairs_succeeded"] = succeeded;
  summary["pairs_rotation_only"] = rotation_only;
  summary["pairs_planar"] = planar;
  summary["matches"] = matches;
  summary["inliers"] = inliers;
  summary["mean_keypoints_per_image"] = rep.mean_keypoints_per_image;
  summary["match_precision"] = json_io::OptionalNumber(pooled.Precision());
  summary["cross_class_matches"] = pooled.cross_class ? Json(*pooled.cross_class) : Json(nullptr);
  summary["cross_class_wrong"] =
      pooled.cross_class ? Json(*pooled.cross_class - pooled.cross_class_correct) : Json(nullptr);
  summary["tolerance"] = {{"rotation_deg", kPairTolerance.rotation_deg}, {"direction_deg", kPairTolerance.direction_deg}};
  summary["pairs_within_tolerance"] = has_truth ? Json(within) : Json(nullptr);
  summary["pairs_succeeded_outside_tolerance"] = has_truth ? Json(succeeded_outside) : Json(nullptr);
  if (has_truth) {
    for (double t : {1.0, 2.0, 5.0, 10.0}) {
      const std::string key = std::to_string(static_cast<int>(t));
      summary["pose_auc"][key] = PoseAuc(pose_errors, t);
      summary["rotation_auc"][key] = PoseAuc(rotation_errors, t);
    }
  }
  Json m;
  m["summary"] = summary;
  m["timing"] = {{"detect_time_s", detect_time_s},
                 {"screen_time_s", rep.screen_time_s},
                 {"match_time_s", rep.match_time_s},
                 {"pose_time_s", rep.pose_time_s},
                 {"temporal_match_time_s", rep.temporal_match_time_s},
                 {"temporal_pose_time_s", rep.temporal_pose_time_s}};
  m["num_cameras"] = rep.num_cameras;
  m["num_frames"] = rep.num_frames;
  m["pairs"] = pairs;
  return m;
}

Json RefinedIntrinsicsToJson(const RefinedIntrinsics& r, const Camera& camera, const IntrinsicsErrors* truth) {
  Json j = {{"model", std::string(CameraModelName(camera.model()))},
            {"param_names", std::string(CameraModelParamNames(camera.model()))},
            {"given", r.given},
            {"refined", r.refined},
            {"stddev", r.stddev.empty() ? Json(nullptr) : Json(r.stddev)}};
  if (r.given.size() >= 4 && r.refined.size() >= 4) {
    j["focal_change_percent"] = {100.0 * (r.refined[0] / r.given[0] - 1.0), 100.0 * (r.refined[1] / r.given[1] - 1.0)};
    j["principal_point_change_px"] = {r.refined[2] - r.given[2], r.refined[3] - r.given[3]};
  }
  j["focal_error_percent"] = truth ? Json(truth->focal_error_percent) : Json(nullptr);
  j["principal_point_error_px"] = truth ? Json(truth->principal_point_error_px) : Json(nullptr);
  j["given_focal_error_percent"] = truth ? Json(truth->given_focal_error_percent) : Json(nullptr);
  j["given_principal_point_error_px"] = truth ? Json(truth->given_principal_point_error_px) : Json(nullptr);
  return j;
}

Json RigResultJson(const RigCalibrationResult& r, const CalibrationScores* truth, double detect_time_s) {
  Json cams = Json::array();
  int calibrated = 0, within = 0, calibrated_outside = 0, open_along_axis = 0, overconfident = 0, stating_sd = 0;
  std::optional<double> max_rot, max_dir, max_across;  // worst over the cameras that have the error; none: null
  for (size_t c = 0; c < r.rig.cameras.size(); ++c) {
    const auto& pose = r.rig.cameras[c].cam_from_rig;
    const RigCameraStats& s = r.camera_stats[c];
    const CameraAgainstTruth* t = CameraTruth(truth, c);
    const CameraAgainstTruth none;
    const CameraAgainstTruth& e = t ? *t : none;
    calibrated += pose.has_value();
    if (e.rotation_error_deg) max_rot = std::max(max_rot.value_or(0.0), *e.rotation_error_deg);
    if (e.translation_direction_error_deg) max_dir = std::max(max_dir.value_or(0.0), *e.translation_direction_error_deg);
    if (e.across_axis_direction_error_deg) max_across = std::max(max_across.value_or(0.0), *e.across_axis_direction_error_deg);
    Json j;
    j["name"] = r.rig.cameras[c].name;
    j["status"] = r.camera_status[c].Text();
    j["calibrated"] = pose.has_value();
    j["position_known"] = pose.has_value();
    j["holds_if_synchronised"] = r.camera_status[c].outcome == CameraOutcome::kCalibratedIfSynchronised;
    const auto& rq = c < r.cam_from_rig_rotation.size() ? r.cam_from_rig_rotation[c] : std::nullopt;
    j["rotation_wxyz"] = rq ? Json({rq->w(), rq->x(), rq->y(), rq->z()}) : Json(nullptr);
    j["cam_from_rig"] = pose ? json_io::PoseToJson(*pose) : Json(nullptr);
    if (pose) {
      const Eigen::Vector3d centre = pose->SourceOriginInTarget();
      j["centre_in_rig"] = {centre.x(), centre.y(), centre.z()};
    } else {
      j["centre_in_rig"] = nullptr;
    }
    j["observations"] = s.observations;
    j["direction_std_deg"] = json_io::OptionalNumber(s.direction_std_deg);
    j["rotation_std_deg"] = json_io::OptionalNumber(s.rotation_std_deg);
    j["direction_jackknife_std_deg"] = json_io::OptionalNumber(s.direction_jackknife_std_deg);
    j["rotation_jackknife_std_deg"] = json_io::OptionalNumber(s.rotation_jackknife_std_deg);
    // With --intrinsics-sd only: the given intrinsics' share of the two deviations.
    if (s.direction_intrinsics_std_deg) j["direction_intrinsics_std_deg"] = *s.direction_intrinsics_std_deg;
    if (s.rotation_intrinsics_std_deg) j["rotation_intrinsics_std_deg"] = *s.rotation_intrinsics_std_deg;
    j["rotation_error_deg"] = json_io::OptionalNumber(e.rotation_error_deg);
    j["translation_direction_error_deg"] = json_io::OptionalNumber(e.translation_direction_error_deg);
    j["position_error_m"] = json_io::OptionalNumber(e.position_error_m);
    // Null without the truth or without a stated deviation; a ratio to a stated 0 is "inf".
    const auto ratio = [](const std::optional<double>& r) {
      return !r ? Json(nullptr) : std::isfinite(*r) ? Json(*r) : Json("inf");
    };
    j["overconfident"] = e.overconfident ? Json(*e.overconfident) : Json(nullptr);
    j["error_sd_ratio"] = {{"rotation", ratio(e.rotation_sd_ratio)}, {"direction", ratio(e.direction_sd_ratio)}};
    overconfident += e.overconfident.value_or(false);
    stating_sd += e.overconfident.has_value();
    j["intrinsics"] = s.intrinsics ? RefinedIntrinsicsToJson(*s.intrinsics, r.rig.cameras[c].camera,
                                                             e.intrinsics ? &*e.intrinsics : nullptr)
                                   : Json(nullptr);
    if (s.time_offset_s || s.readout_s || s.interval_visibility_px) {
      const auto ms = [](const std::optional<double>& v) { return v ? Json(1000.0 * *v) : Json(nullptr); };
      j["capture_time"] = {{"time_offset_ms", ms(s.time_offset_s)},
                           {"time_offset_stddev_ms", ms(s.time_offset_stddev_s)},
                           {"time_offset_determined", !s.time_offset_undetermined},
                           {"time_offset_also_fits_ms", ms(s.time_offset_also_fits_s)},
                           {"time_offset_error_ms", ms(e.time_offset_error_s)},
                           {"readout_ms", ms(s.readout_s)},
                           {"readout_stddev_ms", ms(s.readout_stddev_s)},
                           {"readout_error_ms", ms(e.readout_error_s)},
                           {"interval_visibility_px", json_io::OptionalNumber(s.interval_visibility_px)}};
    }
    if (c < r.partial_centre.size() && r.partial_centre[c] && r.open_axis[c]) {  // placed but for one axis
      const Eigen::Vector3d& axis = *r.open_axis[c];
      const Eigen::Vector3d& across = *r.partial_centre[c];
      j["open_axis"] = {axis.x(), axis.y(), axis.z()};
      j["centre_across_axis"] = {across.x(), across.y(), across.z()};
      j["across_axis_direction_error_deg"] = json_io::OptionalNumber(e.across_axis_direction_error_deg);
      ++open_along_axis;
    }
    const std::optional<bool> ok = CameraWithinTolerance(t);
    j["within_tolerance"] = ok ? Json(*ok) : Json(nullptr);
    within += ok.value_or(false);
    calibrated_outside += pose.has_value() && !ok.value_or(true);
    cams.push_back(j);
  }
  Json edges = Json::array();
  for (const RigEdgeStats& e : r.edges) {
    edges.push_back({{"cam_a", e.cam_a},
                     {"cam_b", e.cam_b},
                     {"inliers", e.inliers},
                     {"used", e.Used()},
                     {"rotation_only", e.rotation_only},
                     {"rotation_outlier", e.outcome == EdgeOutcome::kRotationOutlier},
                     {"rotation_residual_deg", json_io::OptionalNumber(e.rotation_residual_deg)},
                     {"rotation_disagreement_deg", json_io::OptionalNumber(e.rotation_disagreement_deg)},
                     {"direction_disagreement_deg", json_io::OptionalNumber(e.direction_disagreement_deg)},
                     {"rejected", e.outcome == EdgeOutcome::kRejected},
                     {"status", e.status}});
  }
  const bool evaluated = truth != nullptr;
  Json summary = {{"cameras", r.rig.cameras.size()},
                  {"cameras_calibrated", calibrated},
                  {"cameras_calibrated_if_synchronised",
                   std::count_if(r.camera_status.begin(), r.camera_status.end(),
                                 [](const CameraStatus& s) { return s.outcome == CameraOutcome::kCalibratedIfSynchronised; })},
                  {"metric_scale", r.scale_kind == ScaleKind::kMetric},
                  {"scale", ScaleText(r)},
                  {"reprojection_rms_px", r.reprojection_rms_px},
                  {"initial_reprojection_rms_px", r.initial_reprojection_rms_px},
                  {"residual_correlation", r.residual_correlation},
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
                  {"position_eigenvalue_ratio",
                   std::isfinite(r.position_eigenvalue_ratio) ? Json(r.position_eigenvalue_ratio) : Json(nullptr)}};
  if (r.motion_links) {  // the motion stage, which links cameras through the rig's motion (calibrator/stages/motion_links.h)
    summary["motion_links"] = {{"kept", r.motion_links->kept},
                               {"motion", MotionKindName(r.motion_links->motion)},
                               {"cross_time_candidates", r.motion_links->candidates},
                               {"cross_time_pairs", r.motion_links->pairs},
                               {"cross_time_pairs_used", r.motion_links->pairs_used},
                               {"temporal_alternatives_taken", r.motion_links->temporal_alternatives_taken},
                               {"temporal_pairs_disagreeing", r.motion_links->temporal_pairs_disagreeing},
                               {"predicted_views_agreeing", r.motion_links->predicted_views_agreeing},
                               {"predicted_views_contradicting", r.motion_links->predicted_views_contradicting},
                               {"cameras_open_along_axis", open_along_axis},
                               {"time_s", r.motion_links->time_s}};
  }
  summary["tolerance"] = {{"rotation_deg", kCameraTolerance.rotation_deg},
                          {"direction_deg", kCameraTolerance.direction_deg}};
  summary["cameras_within_tolerance"] = evaluated ? Json(within) : Json(nullptr);
  summary["cameras_calibrated_outside_tolerance"] = evaluated ? Json(calibrated_outside) : Json(nullptr);
  summary["cameras_overconfident"] = evaluated ? Json(overconfident) : Json(nullptr);
  summary["cameras_stating_sd"] = evaluated ? Json(stating_sd) : Json(nullptr);
  summary["max_rotation_error_deg"] = json_io::OptionalNumber(evaluated ? max_rot : std::nullopt);
  summary["max_translation_direction_error_deg"] = json_io::OptionalNumber(evaluated ? max_dir : std::nullopt);
  summary["max_across_axis_direction_error_deg"] = json_io::OptionalNumber(evaluated ? max_across : std::nullopt);
  Json m;
  m["summary"] = summary;
  m["timing"] = {{"detect_time_s", detect_time_s},
                 {"match_time_s", r.pairwise.match_time_s},
                 {"pose_time_s", r.pairwise.pose_time_s},
                 {"temporal_match_time_s", r.pairwise.temporal_match_time_s},
                 {"temporal_pose_time_s", r.pairwise.temporal_pose_time_s},
                 {"rotation_averaging_time_s", r.work.rotation_averaging_time_s},
                 {"positions_time_s", r.work.positions_time_s},
                 {"tracks_time_s", r.work.tracks_time_s},
                 {"bundle_adjustment_time_s", r.work.bundle_adjustment_time_s},
                 {"synchronisation_check_time_s", r.work.synchronisation_check_time_s},
                 {"rig_passes", r.work.rig_passes}};
  m["cameras"] = cams;
  Json frames = Json::array();  // per frame index: the rig's pose, or null
  for (const auto& p : r.rig_from_world) frames.push_back(p ? json_io::PoseToJson(*p) : Json(nullptr));
  m["rig_from_world_per_frame"] = frames;
  m["edges"] = edges;
  Json starts = Json::array();
  for (const RigStartSummary& st : r.position_starts) {
    Json diffs = Json::array();
    for (const auto& d : st.direction_difference_deg) diffs.push_back(json_io::OptionalNumber(d));
    starts.push_back({{"source", st.source},
                      {"cost_px2", st.cost},
                      {"observations", st.observations},
                      {"chosen", st.chosen},
                      {"direction_difference_deg", diffs}});
  }
  m["position_starts"] = starts;
  m["warnings"] = r.warnings;
  return m;
}

const RigEdgeStats* RigEdgeOf(const RigCalibrationResult& result, const PairResult& pair) {
  const RigEdgeStats* found = nullptr;
  for (const RigEdgeStats& e : result.edges) {
    if (e.cam_a == pair.cam_a && e.cam_b == pair.cam_b) found = &e;
  }
  return found;
}

Json LabelSourceJson(const LabelSource& source, bool used) {
  Json j = {{"kind", source.KindName()}, {"description", source.Describe()}, {"used", used}};
  if (source.kind == LabelSource::Kind::kFolder) j["folder"] = fs::absolute(source.folder).lexically_normal().string();
  if (source.kind == LabelSource::Kind::kNoisy) {
    j["noise"] = {{"boundary_px", source.noise.boundary_px},
                  {"confusion_rate", source.noise.confusion_rate},
                  {"blob_size_px", source.noise.blob_size_px},
                  {"seed", source.noise.seed}};
  }
  return j;
}

Json PairsJson(const CalibrationRun& run, size_t m, const Json& label_source) {
  const RigCalibrationResult& result = run.results.at(m);
  const CalibrationScores* truth = run.Truth(m);
  Json pairs = Json::array();
  for (size_t p = 0; p < result.pairwise.pairs.size(); ++p) {
    const PairResult& pr = result.pairwise.pairs[p];
    Json pair = PairResultToJson(pr, PairTruth(truth, p));
    pair["pair_type"] = pr.two_view.success ? std::string(PairTypeName(pr.two_view.pair_type)) : "failed";
    const auto ov = run.inputs.overlap.find({pr.cam_a, pr.cam_b});
    pair["overlap"] = ov != run.inputs.overlap.end() ? Json(ov->second) : Json(nullptr);
    pair["rig_edge"] = nullptr;
    if (const RigEdgeStats* e = RigEdgeOf(result, pr)) {
      pair["rig_edge"] = {{"used", e->Used()},
                          {"status", e->status},
                          {"rotation_outlier", e->outcome == EdgeOutcome::kRotationOutlier},
                          {"rotation_residual_deg", json_io::OptionalNumber(e->rotation_residual_deg)},
                          {"rotation_disagreement_deg", json_io::OptionalNumber(e->rotation_disagreement_deg)},
                          {"direction_disagreement_deg", json_io::OptionalNumber(e->direction_disagreement_deg)}};
    }
    pairs.push_back(std::move(pair));
  }
  return {{"semantic_mode", result.semantic_mode},
          {"label_source", label_source},
          {"num_frames", result.pairwise.num_frames},
          {"units",
           {{"median_residual_deg", "median angular epipolar residual of the pair's two-view inliers (deg)"},
            {"rotation_error_deg", "angle of R_est R_true^T (deg), when rig.json has the truth"},
            {"translation_direction_error_deg", "angle between estimated and true baseline directions (deg)"},
            {"rig_edge.rotation_residual_deg",
             "rotation averaging's residual of this pair (deg; 0 where no other path of the view graph constrains it)"},
            {"rig_edge.rotation_disagreement_deg", "the final rig's relative rotation vs this pair's (deg)"},
            {"rig_edge.direction_disagreement_deg",
             "the final rig's baseline direction vs this pair's (deg), when both cameras are placed"}}},
          {"pairs", pairs}};
}

Json IntrinsicsErrorJson(const CalibrationRun& run) {
  const Rig given = CalibratorRig(run.inputs, run.options);
  const auto pinhole = [](const Camera& c) { return Json{{"fx", c.fx()}, {"fy", c.fy()}, {"cx", c.cx()}, {"cy", c.cy()}}; };
  Json cameras = Json::array();
  for (size_t c = 0; c < given.cameras.size() && c < run.inputs.rig.cameras.size(); ++c) {
    const Camera& g = given.cameras[c].camera;
    const Camera& t = run.inputs.rig.cameras[c].camera;
    cameras.push_back({{"name", given.cameras[c].name},
                       {"given", pinhole(g)},
                       {"true", pinhole(t)},
                       {"given_params", g.params()},
                       {"true_params", t.params()},
                       {"focal_error_percent", 100.0 * (g.fx() / t.fx() - 1.0)},
                       {"principal_point_error_px", {g.cx() - t.cx(), g.cy() - t.cy()}}});
  }
  return {{"error", run.options.intrinsics_error.error},
          {"seed", run.options.intrinsics_error.seed},
          {"meaning", "E = error; " + IntrinsicsErrorMeaning() + "; 'true' is the dataset's rig.json"},
          {"cameras", cameras}};
}

Json RigMasksJson(const CalibrationRun& run) {
  if (!run.options.masks) return nullptr;
  const RigMasks& masks = *run.options.masks;
  // ORB spends its budget inside the mask and finds nothing under it to count (FeatureSet).
  const bool counted = run.options.features.type != FeatureType::kOrb;
  Json cameras = Json::array();
  for (size_t c = 0; c < run.inputs.rig.cameras.size(); ++c) {
    const std::string& name = run.inputs.rig.cameras[c].name;
    const CameraMask* m = masks.Of(name);
    Json removed = Json::object();
    for (size_t k = 0; k < run.results.size() && k < run.records.size(); ++k) {
      const std::vector<int>& r = run.records[k].removed_by_mask;
      removed[run.results[k].semantic_mode] = m && counted && c < r.size() ? Json(r[c]) : Json(nullptr);
    }
    cameras.push_back({{"name", name},
                       {"file", m ? Json(fs::absolute(m->file).lexically_normal().string()) : Json(nullptr)},
                       {"hidden_percent", m ? Json(100.0 * m->hidden_fraction) : Json(nullptr)},
                       {"features_removed", removed}});
  }
  return {{"folder", fs::absolute(masks.folder).lexically_normal().string()},
          {"meaning", "each camera's <camera>.png, applied to every frame in every semantic mode: no feature is "
                      "kept where it is black (0); features_removed: keypoints found under the mask and dropped, "
                      "summed over the frames (null for orb, which detects inside the mask only)"},
          {"cameras", cameras}};
}

Json EvaluationJson(const CalibrationRun& run) {
  Json methods = Json::object();
  for (size_t m = 0; m < run.results.size(); ++m) {
    const RigCalibrationResult& r = run.results[m];
    Json entry = PairwiseReportJson(r.pairwise, run.Truth(m), DetectTimeOf(run, m));
    entry["rig"] = RigResultJson(r, run.Truth(m), DetectTimeOf(run, m));
    methods[r.semantic_mode] = entry;
  }
  Json out = {{"methods", methods}, {"features", std::string(FeatureTypeName(run.options.features.type))}};
  if (run.options.intrinsics_error.Enabled()) out["intrinsics_error"] = IntrinsicsErrorJson(run);
  if (run.options.masks) out["masks"] = RigMasksJson(run);
  if (const auto& sd = run.options.rig.bundle_adjustment.given_intrinsics_sd) {
    out["intrinsics_sd"] = {
        {"focal_fraction", sd->focal_fraction},
        {"principal_point_px", sd->principal_point_px},
        {"meaning", "calibrate --intrinsics-sd F,P: the standard deviations of the given fx and fy (a fraction "
                    "of each) and of cx and cy (px); the poses are estimated with the intrinsics held as without "
                    "it, their stated deviations add what these move them by"}};
  }
  return out;
}

}  // namespace rigsim
