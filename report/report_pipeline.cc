// The pipeline of a report, step by step per mode, and the CLI's tables.
#include <cmath>
#include <map>

#include "geometry/json_io.h"
#include "pipeline/calibration_json.h"
#include "pipeline/report_table.h"
#include "report/report_parts.h"

namespace rigsim::report_parts {
using Json = nlohmann::json;

namespace {

// Counts of `values` in log-spaced bins from 0.01 to 1000 px (5 per decade), and the counts below
// and above that range.
Json Histogram(const std::vector<double>& values) {
  constexpr double kLo = 0.01, kHi = 1000.0;
  constexpr int kPerDecade = 5, kBins = 5 * kPerDecade;
  std::vector<int> counts(kBins, 0);
  int below = 0, above = 0;
  for (double v : values) {
    if (!(v >= kLo)) {
      ++below;  // NaN cannot happen; below the range
    } else if (!(v < kHi)) {
      ++above;  // infinite: behind the camera
    } else {
      ++counts[std::min(kBins - 1, int(std::log10(v / kLo) * kPerDecade))];
    }
  }
  Json edges = Json::array();
  for (int i = 0; i <= kBins; ++i) edges.push_back(kLo * std::pow(10.0, double(i) / kPerDecade));
  return {{"edges", edges}, {"counts", counts}, {"below", below}, {"above", above}, {"total", values.size()}};
}

double Median(std::vector<double> v) {
  if (v.empty()) return std::nan("");
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v[v.size() / 2];
}

// Keypoints per class over all views: [[label id, count], ...].
Json KeypointsPerClass(const PairwiseMatchData& md) {
  std::map<int, long> count;
  for (const auto& frame : md.keypoint_classes) {
    for (const auto& cam : frame) {
      for (uint8_t id : cam) ++count[id];
    }
  }
  Json out = Json::array();
  for (const auto& [id, n] : count) out.push_back({id, n});
  return out;
}

Json Rotation(const std::optional<Eigen::Quaterniond>& q) {
  return q ? Json({q->w(), q->x(), q->y(), q->z()}) : Json(nullptr);
}

}  // namespace

Json PipelineData(ReportContext& ctx) {
  const CalibrationRun& run = ctx.run;
  const Rig& rig = run.inputs.rig;
  Json modes = Json::array();
  for (size_t m = 0; m < run.results.size(); ++m) {
    const RigCalibrationResult& r = run.results[m];
    const RigCalibrationDetails* d = ctx.Details(m);
    Json mode = {{"name", r.semantic_mode}, {"scale", ScaleText(r)}, {"warnings", r.warnings}};
    // 1. Keypoints.
    long keypoints = 0;
    if (d) {
      for (const auto& frame : d->matches.keypoints) {
        for (const auto& cam : frame) keypoints += long(cam.size());
      }
      mode["keypoints_per_class"] = KeypointsPerClass(d->matches);
    }
    mode["keypoints"] = keypoints;
    mode["mean_keypoints_per_image"] = r.pairwise.mean_keypoints_per_image;
    // 2. The view graph: every pair's edge, used or why not.
    Json edges = Json::array();
    for (const RigEdgeStats& e : r.edges) {
      edges.push_back({{"a", rig.FindCamera(e.cam_a)},
                       {"b", rig.FindCamera(e.cam_b)},
                       {"inliers", e.inliers},
                       {"used", e.Used()},
                       {"rotation_only", e.rotation_only},
                       {"rotation_outlier", e.outcome == EdgeOutcome::kRotationOutlier},
                       {"rotation_residual_deg", json_io::OptionalNumber(e.rotation_residual_deg)},
                       {"rotation_disagreement_deg", json_io::OptionalNumber(e.rotation_disagreement_deg)},
                       {"status", e.status}});
    }
    mode["edges"] = edges;
    mode["rotation_outliers"] = r.num_rotation_outliers;
    // 3. Rotation averaging, then the bundle adjustment: each camera's rotation and its error.
    Json cameras = Json::array();
    for (size_t c = 0; c < rig.cameras.size(); ++c) {
      const RigCameraStats& s = r.camera_stats[c];
      const CalibrationScores* truth = run.Truth(m);
      const CameraAgainstTruth t = truth ? truth->cameras.at(c) : CameraAgainstTruth{};
      Json cam = {{"name", rig.cameras[c].name},
                  {"status", r.camera_status[c].Text()},
                  {"observations", s.observations},
                  {"direction_std_deg", json_io::OptionalNumber(s.direction_std_deg)},
                  {"rotation_error_deg", json_io::OptionalNumber(t.rotation_error_deg)},
                  {"translation_direction_error_deg", json_io::OptionalNumber(t.translation_direction_error_deg)},
                  {"position_error_m", nullptr},
                  {"rotation_averaging_error_deg", nullptr}};
      if (ctx.HasTruth()) {
        const CameraScore& score = ctx.aligned[m].scores.cameras[c];
        cam["position_error_m"] = json_io::OptionalNumber(score.position_error_m);  // after the scale fit
        if (d && c < d->rotation_averaging.size() && d->rotation_averaging[c] && d->rotation_averaging[0]) {
          // Against the truth with camera 0 as the rig frame, as the final errors are.
          const Rig& truth = *run.inputs.truth;
          const Eigen::Quaterniond true_c0 =
              truth.cameras[c].cam_from_rig->rotation * truth.cameras[0].cam_from_rig->rotation.inverse();
          const Eigen::Quaterniond est_c0 = *d->rotation_averaging[c] * d->rotation_averaging[0]->inverse();
          cam["rotation_averaging_error_deg"] = est_c0.angularDistance(true_c0) * 180.0 / M_PI;
        }
      }
      cam["rotation_averaging_wxyz"] = d && c < d->rotation_averaging.size() ? Rotation(d->rotation_averaging[c]) : Json(nullptr);
      cameras.push_back(cam);
    }
    mode["cameras"] = cameras;
    // 4. The bundle adjustment.
    Json ba = {{"tracks", r.num_tracks},
               {"conflicting_tracks", r.num_conflicting_tracks},
               {"points", r.num_points},
               {"observations", r.num_observations},
               {"filtered_observations", r.num_filtered_observations},
               {"initial_rms_px", r.initial_reprojection_rms_px},
               {"final_rms_px", r.reprojection_rms_px},
               {"frames", r.num_frames},
               {"frames_posed", r.num_frames_posed},
               {"rig_motion_estimated", r.rig_motion_estimated},
               {"temporal_pairs_used", r.num_temporal_pairs_used}};
    if (d) {
      ba["initial_residuals"] = Histogram(d->initial_residuals_px);
      ba["final_residuals"] = Histogram(d->final_residuals_px);
      ba["initial_median_px"] = json_io::OptionalNumber(Median(d->initial_residuals_px));
      ba["final_median_px"] = json_io::OptionalNumber(Median(d->final_residuals_px));
    }
    mode["bundle_adjustment"] = ba;
    if (ctx.HasTruth()) mode["scores"] = RigScoresToJson(ctx.aligned[m].scores);
    modes.push_back(mode);
  }
  // The CLI's tables, as calibrate and evaluate print them; not the pairwise summary line, whose
  // stage times would make two reports of the same seed differ.
  Json tables = {{"pairs", FormatPairTable(run)},
                 {"rig", FormatRigTable(run)},
                 {"rig_summary", FormatRigSummary(run)},
                 {"times", FormatTimeTable(run)}};
  if (ctx.HasTruth()) {
    std::vector<RigScores> scores;
    for (const AlignedEstimate& a : ctx.aligned) scores.push_back(a.scores);
    tables["evaluate"] = FormatRigScores(scores);
  }
  return {{"modes", modes}, {"tables", tables}};
}

}  // namespace rigsim::report_parts
