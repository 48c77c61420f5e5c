#include "evaluation/rig_scores.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>

#include "common/format.h"
#include "evaluation/pose_errors.h"
#include "evaluation/verdicts.h"

namespace rigsim {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

double Median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

// Centre of the camera in camera 0's frame, from cam_from_cam0.
Eigen::Vector3d Centre(const Rigid3d& cam_from_cam0) { return cam_from_cam0.Inverse().translation; }

double AngleDeg(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return RadToDeg(std::atan2(a.cross(b).norm(), a.dot(b)));
}

std::optional<double> Max(const std::vector<double>& v) {
  if (v.empty()) return std::nullopt;
  return *std::max_element(v.begin(), v.end());
}

}  // namespace

bool CapturesWithReference(const Rig& truth, size_t c) {
  const RigCamera &cam = truth.cameras.at(c), &ref = truth.cameras.at(0);
  return cam.time_offset_s == ref.time_offset_s && cam.readout_s == ref.readout_s;
}

RigScores ScoreRig(const Rig& truth, const RigEstimate& estimate, const TruthAccuracy& accuracy) {
  const size_t n = truth.cameras.size();
  if (!truth.HasAllPoses()) throw std::invalid_argument("ScoreRig: the truth needs every camera's cam_from_rig");
  if (estimate.cam_from_rig.size() != n || estimate.rotation_only.size() != n || estimate.open_axis.size() != n) {
    throw std::invalid_argument("ScoreRig: the estimate needs one entry per camera of the truth");
  }
  if (!(accuracy.rotation_deg >= 0.0) || !(accuracy.position_m >= 0.0)) {
    throw std::invalid_argument("ScoreRig: the truth's accuracy must be 0 or more");
  }
  RigScores s;
  s.method = estimate.method;
  s.truth_accuracy = accuracy;
  s.metric = estimate.metric;
  s.notes = estimate.notes;
  // Both rigs re-expressed with camera 0 as the rig frame.
  const Rigid3d true_cam0_from_rig = *truth.cameras[0].cam_from_rig;
  std::vector<Rigid3d> true_from_cam0(n);
  for (size_t c = 0; c < n; ++c) true_from_cam0[c] = *truth.cameras[c].cam_from_rig * true_cam0_from_rig.Inverse();
  const std::optional<Rigid3d>& est_cam0 = estimate.cam_from_rig[0];
  std::vector<std::optional<Rigid3d>> est_from_cam0(n);
  std::vector<std::optional<Eigen::Quaterniond>> est_rotation(n);  // of cam_c_from_cam0
  std::vector<std::optional<OpenAxisCentre>> est_open_axis(n);      // in camera 0's frame
  for (size_t c = 0; c < n; ++c) {
    if (!est_cam0) break;  // without camera 0 nothing is in the gauge
    if (estimate.cam_from_rig[c]) {
      est_from_cam0[c] = *estimate.cam_from_rig[c] * est_cam0->Inverse();
      est_rotation[c] = est_from_cam0[c]->rotation;
    } else if (estimate.rotation_only[c]) {
      est_rotation[c] = *estimate.rotation_only[c] * est_cam0->rotation.inverse();
      if (const std::optional<OpenAxisCentre>& open = estimate.open_axis[c]) {
        // The centre is c_across + t axis for an unknown t: its part across the axis in camera 0's
        // frame is that of any such point.
        const Eigen::Vector3d axis = est_cam0->rotation * open->axis;
        est_open_axis[c] = OpenAxisCentre{axis, AcrossAxis(axis, *est_cam0 * open->centre_across_axis)};
      }
    }
  }
  if (!est_cam0) s.notes.push_back("no pose for the reference camera " + truth.cameras[0].name + ": nothing scored");

  // Scale of the position errors: least squares of s C_est onto C_true over the placed cameras.
  double num = 0.0, den = 0.0;
  for (size_t c = 1; c < n; ++c) {
    if (!est_from_cam0[c]) continue;
    num += Centre(*est_from_cam0[c]).dot(Centre(true_from_cam0[c]));
    den += Centre(*est_from_cam0[c]).squaredNorm();
  }
  s.scale = estimate.metric ? 1.0 : (den > 0 ? num / den : 1.0);

  std::vector<double> rotation_errors, direction_errors, position_errors, camera_pose_errors, across_errors;
  for (size_t c = 0; c < n; ++c) {
    CameraScore cs;
    cs.name = truth.cameras[c].name;
    cs.posed = est_from_cam0[c].has_value();
    cs.has_rotation = est_rotation[c].has_value();
    cs.open_axis = est_open_axis[c].has_value();
    cs.if_synchronised = cs.posed && c < estimate.if_synchronised.size() && estimate.if_synchronised[c];
    s.cameras_if_synchronised += cs.if_synchronised;
    s.cameras_posed += cs.posed;
    s.cameras_rotation_only += cs.has_rotation && !cs.posed && !cs.open_axis;
    s.cameras_open_axis += cs.open_axis;
    if (c == 0) {
      cs.pose_error_deg = cs.posed ? 0.0 : kInf;
      if (cs.posed) cs.rotation_error_deg = 0.0;
      s.cameras.push_back(cs);
      continue;
    }
    if (cs.has_rotation) {
      cs.rotation_error_deg = RadToDeg(est_rotation[c]->angularDistance(true_from_cam0[c].rotation));
      rotation_errors.push_back(*cs.rotation_error_deg);
    }
    if (cs.posed) {
      const Eigen::Vector3d est_centre = Centre(*est_from_cam0[c]), true_centre = Centre(true_from_cam0[c]);
      if (est_centre.norm() > 1e-12 && true_centre.norm() > 1e-12) {
        cs.direction_error_deg = AngleDeg(est_centre, true_centre);
        direction_errors.push_back(*cs.direction_error_deg);
      }
      cs.position_error_m = (s.scale * est_centre - true_centre).norm();
      position_errors.push_back(*cs.position_error_m);
    }
    // A camera at camera 0's centre has no direction: its rotation is its whole pose.
    const bool true_has_direction = Centre(true_from_cam0[c]).norm() > 1e-9;
    cs.pose_error_deg = PoseErrorDeg(cs.posed, cs.rotation_error_deg, cs.direction_error_deg, true_has_direction);
    camera_pose_errors.push_back(cs.pose_error_deg);
    double placed_error_deg = cs.pose_error_deg;  // of what the estimate claims of the camera's place
    if (cs.open_axis) {
      const OpenAxisCentre& open = *est_open_axis[c];
      const Eigen::Vector3d true_centre = Centre(true_from_cam0[c]);
      cs.across_axis_direction_error_deg = AcrossAxisDirectionErrorDeg(open.axis, open.centre_across_axis, true_centre);
      if (cs.across_axis_direction_error_deg) across_errors.push_back(*cs.across_axis_direction_error_deg);
      const bool true_has_across = AcrossAxis(open.axis, true_centre).norm() > 1e-9;
      placed_error_deg = OpenAxisErrorDeg(cs.rotation_error_deg, cs.across_axis_direction_error_deg, true_has_across);
    }
    const auto stated = [c](const std::vector<std::optional<double>>& sd) {
      return c < sd.size() ? sd[c] : std::nullopt;
    };
    // Both cameras' truths are off: the relative rotation and the centres' difference by sqrt(2).
    const double true_distance = Centre(true_from_cam0[c]).norm();
    const double truth_direction_sd_deg =
        true_distance > 1e-9 ? RadToDeg(std::sqrt(2.0) * accuracy.position_m / true_distance) : 0.0;
    const StatedError rotation{cs.rotation_error_deg, stated(estimate.rotation_std_deg),
                               std::sqrt(2.0) * accuracy.rotation_deg};
    const StatedError direction{cs.posed ? cs.direction_error_deg : std::nullopt, stated(estimate.direction_std_deg),
                                truth_direction_sd_deg};
    cs.rotation_sd_ratio = rotation.Ratio();
    cs.direction_sd_ratio = direction.Ratio();
    if (!cs.if_synchronised || CapturesWithReference(truth, c)) cs.overconfident = Overconfident({rotation, direction});
    s.cameras_stating_sd += cs.overconfident.has_value();
    s.overconfident += cs.overconfident.value_or(false);
    // A pose claimed if synchronised is claimed outright where the truth's camera captured with
    // camera 0: the condition holds, so a wrong pose is confidently wrong there too.
    if (cs.if_synchronised) s.wrong_if_synchronised += ConfidentlyWrong(true, placed_error_deg);
    if (!cs.if_synchronised || CapturesWithReference(truth, c)) {
      s.confidently_wrong += ConfidentlyWrong(cs.posed || cs.open_axis, placed_error_deg);
    }
    s.cameras.push_back(cs);
  }

  std::vector<double> pair_pose_errors;
  for (size_t a = 0; a < n; ++a) {
    for (size_t b = a + 1; b < n; ++b) {
      PairScore ps;
      ps.cam_a = truth.cameras[a].name;
      ps.cam_b = truth.cameras[b].name;
      const Rigid3d true_ba = true_from_cam0[b] * true_from_cam0[a].Inverse();
      if (est_rotation[a] && est_rotation[b]) {
        ps.rotation_error_deg =
            RadToDeg((*est_rotation[b] * est_rotation[a]->inverse()).angularDistance(true_ba.rotation));
      }
      const bool posed = est_from_cam0[a] && est_from_cam0[b];
      if (posed) {
        const Rigid3d est_ba = *est_from_cam0[b] * est_from_cam0[a]->Inverse();
        ps.direction_error_deg = TranslationDirectionErrorDeg(est_ba, true_ba);
      }
      ps.pose_error_deg =
          PoseErrorDeg(posed, ps.rotation_error_deg, ps.direction_error_deg, true_ba.translation.norm() > 1e-9);
      pair_pose_errors.push_back(ps.pose_error_deg);
      s.pairs.push_back(ps);
    }
  }

  s.max_rotation_error_deg = Max(rotation_errors);
  s.max_direction_error_deg = Max(direction_errors);
  s.max_position_error_m = Max(position_errors);
  s.max_across_axis_direction_error_deg = Max(across_errors);
  if (!rotation_errors.empty()) s.median_rotation_error_deg = Median(rotation_errors);
  if (!direction_errors.empty()) s.median_direction_error_deg = Median(direction_errors);
  for (int t = 0; t < 4; ++t) {
    s.auc_cameras[t] = PoseAuc(camera_pose_errors, kAucThresholdsDeg[t]);
    s.auc_pairs[t] = PoseAuc(pair_pose_errors, kAucThresholdsDeg[t]);
  }
  s.success_1deg = RigSucceeds(est_cam0.has_value(), camera_pose_errors, kSuccessLimitsDeg[0]);
  s.success_2deg = RigSucceeds(est_cam0.has_value(), camera_pose_errors, kSuccessLimitsDeg[1]);
  return s;
}

std::vector<CameraErrors> CalibrationCameraErrors(const Rig& truth, const RigEstimate& estimate) {
  const size_t n = truth.cameras.size();
  if (!truth.HasAllPoses()) throw std::invalid_argument("CalibrationCameraErrors: the truth needs every camera's cam_from_rig");
  if (estimate.cam_from_rig.size() != n || estimate.rotation_only.size() != n || estimate.open_axis.size() != n) {
    throw std::invalid_argument("CalibrationCameraErrors: the estimate needs one entry per camera of the truth");
  }
  std::vector<CameraErrors> out(n);
  const Rigid3d rig_from_cam0 = truth.cameras[0].cam_from_rig->Inverse();
  for (size_t c = 0; c < n; ++c) {
    const std::optional<Rigid3d>& est = estimate.cam_from_rig[c];
    // The truth with camera 0 as the rig frame (the estimate's gauge).
    const Rigid3d gt = *truth.cameras[c].cam_from_rig * rig_from_cam0;
    CameraErrors& e = out[c];
    if (!est) {
      if (!estimate.rotation_only[c]) continue;
      e.rotation_error_deg = RotationDifferenceDeg(*estimate.rotation_only[c], gt.rotation);
      if (const std::optional<OpenAxisCentre>& open = estimate.open_axis[c]) {
        e.across_axis_direction_error_deg =
            AcrossAxisDirectionErrorDeg(open->axis, open->centre_across_axis, gt.SourceOriginInTarget());
      }
      continue;
    }
    e.rotation_error_deg = RotationErrorDeg(*est, gt);
    const Eigen::Vector3d c_est = est->SourceOriginInTarget(), c_gt = gt.SourceOriginInTarget();
    if (c_est.norm() > 1e-9 && c_gt.norm() > 1e-9) e.direction_error_deg = AngleBetweenDeg(c_est, c_gt);
    if (estimate.metric) e.position_error_m = (c_est - c_gt).norm();
  }
  return out;
}

namespace {

nlohmann::json Opt(const std::optional<double>& v) { return v ? nlohmann::json(*v) : nlohmann::json(nullptr); }
nlohmann::json Finite(double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr); }
// A ratio to a stated deviation of 0 is +inf: JSON has no infinity, so "inf" says it.
nlohmann::json OptFinite(const std::optional<double>& v) {
  if (!v) return nullptr;
  return std::isfinite(*v) ? nlohmann::json(*v) : nlohmann::json("inf");
}

std::string Deg(const std::optional<double>& v, const char* format = "%.3f deg") {
  if (!v) return "-";
  char buf[32];
  std::snprintf(buf, sizeof buf, format, *v);
  return buf;
}

}  // namespace

nlohmann::json RigScoresToJson(const RigScores& s) {
  nlohmann::json cameras = nlohmann::json::array(), pairs = nlohmann::json::array();
  for (const CameraScore& c : s.cameras) {
    cameras.push_back({{"name", c.name},
                       {"posed", c.posed},
                       {"has_rotation", c.has_rotation},
                       {"open_along_axis", c.open_axis},
                       {"rotation_error_deg", Opt(c.rotation_error_deg)},
                       {"translation_direction_error_deg", Opt(c.direction_error_deg)},
                       {"across_axis_direction_error_deg", Opt(c.across_axis_direction_error_deg)},
                       {"position_error_m", Opt(c.position_error_m)},
                       {"pose_error_deg", Finite(c.pose_error_deg)},
                       {"overconfident", c.overconfident ? nlohmann::json(*c.overconfident) : nlohmann::json(nullptr)},
                       {"error_sd_ratio",
                        {{"rotation", OptFinite(c.rotation_sd_ratio)}, {"direction", OptFinite(c.direction_sd_ratio)}}}});
  }
  for (const PairScore& p : s.pairs) {
    pairs.push_back({{"cam_a", p.cam_a},
                     {"cam_b", p.cam_b},
                     {"rotation_error_deg", Opt(p.rotation_error_deg)},
                     {"translation_direction_error_deg", Opt(p.direction_error_deg)},
                     {"pose_error_deg", Finite(p.pose_error_deg)}});
  }
  nlohmann::json auc_cameras, auc_pairs;
  for (int t = 0; t < 4; ++t) {
    const std::string key = std::to_string(static_cast<int>(kAucThresholdsDeg[t]));
    auc_cameras[key] = s.auc_cameras[t];
    auc_pairs[key] = s.auc_pairs[t];
  }
  return {{"method", s.method},
          {"summary",
           {{"cameras", s.cameras.size()},
            {"cameras_posed", s.cameras_posed},
            {"cameras_rotation_only", s.cameras_rotation_only},
            {"cameras_open_axis", s.cameras_open_axis},
            {"success_1deg", s.success_1deg},
            {"success_2deg", s.success_2deg},
            {"confidently_wrong", s.confidently_wrong},
            {"overconfident", s.overconfident},
            {"cameras_stating_sd", s.cameras_stating_sd},
            {"cameras_if_synchronised", s.cameras_if_synchronised},
            {"wrong_if_synchronised", s.wrong_if_synchronised},
            {"max_rotation_error_deg", Opt(s.max_rotation_error_deg)},
            {"median_rotation_error_deg", Opt(s.median_rotation_error_deg)},
            {"max_translation_direction_error_deg", Opt(s.max_direction_error_deg)},
            {"median_translation_direction_error_deg", Opt(s.median_direction_error_deg)},
            {"max_position_error_m", Opt(s.max_position_error_m)},
            {"max_across_axis_direction_error_deg", Opt(s.max_across_axis_direction_error_deg)},
            {"metric", s.metric},
            {"position_scale", s.scale},
            {"truth_accuracy", {{"rotation_deg", s.truth_accuracy.rotation_deg},
                                {"position_m", s.truth_accuracy.position_m}}},
            {"pose_auc_cameras", auc_cameras},
            {"pose_auc_pairs", auc_pairs}}},
          {"cameras", cameras},
          {"pairs", pairs},
          {"notes", s.notes}};
}

std::string FormatRigScores(const std::vector<RigScores>& all) {
  std::string out;
  char line[256];
  // The errors over the stated deviations, when an estimate states them (a calibration folder).
  const bool stated = std::any_of(all.begin(), all.end(), [](const RigScores& s) {
    return std::any_of(s.cameras.begin(), s.cameras.end(),
                       [](const CameraScore& c) { return c.rotation_sd_ratio || c.direction_sd_ratio; });
  });
  const auto ratio = [](const std::optional<double>& r) { return r ? Deg(*r, "%.1f") : std::string("-"); };
  std::snprintf(line, sizeof line, "%-12s %-12s %12s %12s %12s%s  %s\n", "camera", "method", "rot_err", "t_dir_err",
                "pos_err", stated ? "   rot/sd   dir/sd" : "", "pose");
  out += line;
  if (all.empty()) return out;
  for (size_t c = 0; c < all[0].cameras.size(); ++c) {
    for (size_t m = 0; m < all.size(); ++m) {
      const CameraScore& cs = all[m].cameras[c];
      // In the truth's metres, whether the estimate is metric or its scale was fitted (said below).
      const std::string pos = Deg(cs.position_error_m, "%.3f m");
      const char* pose = c == 0        ? (cs.posed ? "reference" : "missing")
                         : cs.if_synchronised ? "full pose if synchronised"
                         : cs.posed     ? "full pose"
                         : cs.open_axis ? "placed but for one axis (t_dir_err: its centre across the axis)"
                         : cs.has_rotation ? "rotation only"
                                           : "missing";
      const std::optional<double>& direction = cs.open_axis ? cs.across_axis_direction_error_deg : cs.direction_error_deg;
      char ratios[64] = "";
      if (stated) {
        std::snprintf(ratios, sizeof ratios, " %8s %8s", ratio(cs.rotation_sd_ratio).c_str(),
                      ratio(cs.direction_sd_ratio).c_str());
      }
      std::snprintf(line, sizeof line, "%-12s %-12s %12s %12s %12s%s  %s%s\n", m == 0 ? cs.name.c_str() : "",
                    all[m].method.c_str(), Deg(cs.rotation_error_deg).c_str(), Deg(direction).c_str(), pos.c_str(),
                    ratios, pose, cs.overconfident.value_or(false) ? ", overconfident" : "");
      out += line;
    }
  }
  out += "\n";
  for (const RigScores& s : all) {
    std::snprintf(line, sizeof line,
                  "%s: %d/%zu cameras with a full pose, worst rotation %s, worst direction %s; pose AUC over pairs "
                  "@1/2/5/10 deg %.2f/%.2f/%.2f/%.2f; every camera within %g deg: %s%s\n",
                  s.method.c_str(), s.cameras_posed, s.cameras.size(), Deg(s.max_rotation_error_deg).c_str(),
                  Deg(s.max_direction_error_deg).c_str(), s.auc_pairs[0], s.auc_pairs[1], s.auc_pairs[2], s.auc_pairs[3],
                  kSuccessLimitsDeg[1], s.success_2deg ? "yes" : "no",
                  s.confidently_wrong > 0 ? (", " + std::to_string(s.confidently_wrong) + " camera(s) placed > " +
                                             Deg(kConfidentlyWrongDeg, "%g deg") + " off").c_str()
                                          : "");
    out += line;
    if (s.cameras_stating_sd > 0) {
      const std::string truth_sd =
          s.truth_accuracy.Exact() ? ""
                                   : "; sd: the stated one and the truth's own, " + Deg(s.truth_accuracy.rotation_deg, "%g deg") +
                                         " and " + Deg(s.truth_accuracy.position_m, "%g m") + " per camera (--truth-sd)";
      out += "  overconfident: " + std::to_string(s.overconfident) + " of " + std::to_string(s.cameras_stating_sd) +
             " camera(s) that state a standard deviation (rot/sd, dir/sd: an error beyond " +
             Fixed(kOverconfidentSigmas, 0) + " sd and " + Deg(kOverconfidentFloorDeg, "%g deg") + truth_sd + ")\n";
    }
    if (s.cameras_if_synchronised > 0) {
      out += "  " + std::to_string(s.cameras_if_synchronised) + " camera(s) posed if synchronised (the rig's path " +
             "cannot show a time offset), " + std::to_string(s.wrong_if_synchronised) + " of them > " +
             Deg(kConfidentlyWrongDeg, "%g deg") + " off\n";
    }
    if (s.cameras_open_axis > 0) {
      out += "  " + std::to_string(s.cameras_open_axis) + " camera(s) placed but for one axis (no full pose), worst " +
             "direction across the axis " + Deg(s.max_across_axis_direction_error_deg) + "\n";
    }
    if (!s.metric && s.max_position_error_m) {
      out += "  pos_err: in the truth's metres after fitting the estimate's scale (x" + Deg(s.scale, "%.4g") +
             "): the estimate is not metric (--scale metric takes it as metres)\n";
    }
    for (const std::string& note : s.notes) out += "  note: " + note + "\n";
  }
  return out;
}

}  // namespace rigsim
