#include "pipeline/report_table.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "common/format.h"
#include "evaluation/verdicts.h"
#include "pipeline/calibration_json.h"

namespace rigsim {
namespace {

std::string Fmt(const char* fmt, double v) {
  char buf[64];
  std::snprintf(buf, sizeof(buf), fmt, v);
  return buf;
}

std::string Opt(const std::optional<double>& v, const char* fmt) { return v ? Fmt(fmt, *v) : "-"; }

std::optional<double> Percent(const std::optional<double>& fraction) {
  if (!fraction) return std::nullopt;
  return 100.0 * *fraction;
}

std::optional<double> OverlapOf(const OverlapTable& overlap, const PairResult& p) {
  const auto it = overlap.find({p.cam_a, p.cam_b});
  if (it == overlap.end()) return std::nullopt;
  return it->second;
}

bool IsNeighbour(const OverlapTable& overlap, const PairResult& p) {
  const auto o = OverlapOf(overlap, p);
  return overlap.empty() || (o && *o >= kNeighbourOverlap);
}

std::optional<double> Median(std::vector<double> v) {
  if (v.empty()) return std::nullopt;
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

}  // namespace

std::string FormatPairTable(const CalibrationRun& run) {
  const OverlapTable& overlap = run.inputs.overlap;
  std::ostringstream out;
  char line[256];
  std::snprintf(line, sizeof(line), "%-14s %7s  %-10s %8s %8s %9s %10s %10s  %-13s  %s\n", "pair", "overlap",
                "method", "matches", "inliers", "precision", "rot_err", "t_dir_err", "type", "status");
  out << line;
  if (run.results.empty()) return out.str();
  // Pairs screened out in every method share one line (each reason is in pairs.json): a ring of
  // n cameras has about n^2/2 pairs, most of which see nothing in common.
  std::string screened;
  int num_screened = 0;
  for (size_t i = 0; i < run.results[0].pairwise.pairs.size(); ++i) {
    const bool all_screened = std::all_of(run.results.begin(), run.results.end(), [i](const RigCalibrationResult& r) {
      return r.pairwise.pairs[i].screened_out;
    });
    if (all_screened) {
      const PairResult& p = run.results[0].pairwise.pairs[i];
      const std::optional<double> o = OverlapOf(overlap, p);
      screened += (screened.empty() ? "" : ", ") + p.cam_a + "-" + p.cam_b + (o ? " (" + Fmt("%.0f%%", 100.0 * *o) + ")" : "");
      ++num_screened;
      continue;
    }
    for (size_t m = 0; m < run.results.size(); ++m) {
      const PairResult& p = run.results[m].pairwise.pairs[i];
      const CalibrationScores* scores = run.Truth(m);
      const PairAgainstTruth* truth = scores ? &scores->pairs[i] : nullptr;
      const PairAgainstTruth none;
      const PairAgainstTruth& t = truth ? *truth : none;
      const std::string pair = m == 0 ? p.cam_a + "-" + p.cam_b : "";
      const std::string ov = m == 0 ? Opt(Percent(OverlapOf(overlap, p)), "%.0f%%") : "";
      // Type: what the matches determine (two_view.h: general, planar, rotation-only).
      const TwoViewEstimate& tv = p.two_view;
      const std::string type = tv.success ? std::string(PairTypeName(tv.pair_type)) : "-";
      std::string status = PairStatus(p);
      if (p.Solved() && !PairWithinTolerance(p, truth).value_or(true)) status += " (outside tolerance against the truth)";
      if (p.Solved() && tv.rival) {  // two_view.h: the matches alone do not decide between the two
        status += "; another pose fits its matches as well: baseline " + Fixed(tv.rival->direction_deg, 0) +
                  " deg away, turned " + Fixed(tv.rival->rotation_deg, 1) + " deg";
      }
      // A pair the rig uses but whose own rotation is farther from the rig's than a camera's
      // tolerance: the rig, made from every pair and track, is the estimate to take, not the pair's.
      const RigEdgeStats* edge = p.Solved() ? RigEdgeOf(run.results[m], p) : nullptr;
      if (edge && edge->Used() && edge->rotation_disagreement_deg.value_or(0.0) > kCameraTolerance.rotation_deg) {
        status += "; its rotation is " + Fixed(*edge->rotation_disagreement_deg, 1) +
                  " deg from the rig's (the rig's poses, from every pair and track, are the ones to use)";
      }
      // The status goes last and whole: it says what to do.
      std::snprintf(line, sizeof(line), "%-14s %7s  %-10s %8d %8d %9s %10s %10s  %-13s  ", pair.c_str(), ov.c_str(),
                    run.results[m].semantic_mode.c_str(), tv.num_matches, tv.num_inliers,
                    Opt(Percent(t.match_precision), "%.1f%%").c_str(),
                    tv.success ? Opt(t.rotation_error_deg, "%.3f deg").c_str() : "-",
                    tv.success ? Opt(t.translation_direction_error_deg, "%.2f deg").c_str() : "-", type.c_str());
      out << line << status << "\n";
    }
  }
  if (num_screened > 0) {
    out << Count(num_screened, "pair") << " screened out in every method (no shared view found among the strongest keypoints; pairs.json says why "
           "for each): "
        << screened << "\n";
  }
  return out.str();
}

std::string FormatSummary(const CalibrationRun& run) {
  const OverlapTable& overlap = run.inputs.overlap;
  std::ostringstream out;
  for (size_t m = 0; m < run.results.size(); ++m) {
    const CalibrationReport& r = run.results[m].pairwise;
    const CalibrationScores* truth = run.Truth(m);
    std::vector<double> rot, tdir, prec;
    int neighbours = 0, solved = 0, solved_below = 0;
    for (size_t i = 0; i < r.pairs.size(); ++i) {
      const PairResult& p = r.pairs[i];
      if (!IsNeighbour(overlap, p)) {
        solved_below += p.Solved();
        continue;
      }
      ++neighbours;
      const PairAgainstTruth* t = truth ? &truth->pairs[i] : nullptr;
      if (t && t->match_precision) prec.push_back(*t->match_precision);
      if (!p.Solved()) continue;
      ++solved;
      if (t && t->rotation_error_deg) rot.push_back(*t->rotation_error_deg);
      if (t && t->translation_direction_error_deg) tdir.push_back(*t->translation_direction_error_deg);
    }
    // Without overlap.json (photos) every pair counts: whether two views overlap is not known.
    const std::string rule = Fmt("%.0f%%", 100.0 * kNeighbourOverlap);
    out << run.results[m].semantic_mode << ": " << solved << "/" << neighbours
        << (overlap.empty() ? " pairs solved" : " pairs of at least " + rule + " overlap solved");
    if (solved_below > 0) {
      out << " (and " << Count(solved_below, "pair") << " below " << rule
          << ", not in the medians)";
    }
    out << ", median rotation error " << Opt(Median(rot), "%.4f deg")
        << ", median translation direction error " << Opt(Median(tdir), "%.2f deg") << ", median match precision "
        << Opt(Percent(Median(prec)), "%.1f%%") << "; "
        << Fmt("%.0f", r.mean_keypoints_per_image) << " keypoints/image; time detect "
        << Fmt("%.2f s", m < run.records.size() ? run.records[m].detect_time_s : 0.0) << ", screen " << Fmt("%.2f s", r.screen_time_s) << ", match "
        << Fmt("%.2f s", r.match_time_s + r.temporal_match_time_s) << ", pose "
        << Fmt("%.2f s", r.pose_time_s + r.temporal_pose_time_s) << " (summed over threads)\n";
  }
  return out.str();
}

std::string FormatRigTable(const CalibrationRun& run) {
  const std::vector<RigCalibrationResult>& results = run.results;
  std::ostringstream out;
  char line[512];
  std::snprintf(line, sizeof(line), "%-10s %-10s %10s %10s %10s %10s %8s  %s\n", "camera", "method", "rot_err",
                "t_dir_err", "t_dir_std", "pos_err", "obs", "status");
  out << line;
  if (results.empty()) return out.str();
  for (size_t c = 0; c < results[0].rig.cameras.size(); ++c) {
    for (size_t m = 0; m < results.size(); ++m) {
      const RigCalibrationResult& r = results[m];
      const RigCameraStats& st = r.camera_stats[c];
      const CalibrationScores* scores = run.Truth(m);
      const CameraAgainstTruth* truth = scores ? &scores->cameras[c] : nullptr;
      const CameraAgainstTruth none;
      const CameraAgainstTruth& t = truth ? *truth : none;
      // A camera placed but for one axis has the direction of its centre across the axis in t_dir_err.
      const bool open_axis = r.camera_status[c].outcome == CameraOutcome::kOpenAlongAxis;
      std::string status = r.camera_status[c].Text();
      if (open_axis && t.across_axis_direction_error_deg) status += " (t_dir_err: its centre across the axis)";
      if ((r.rig.cameras[c].cam_from_rig || open_axis) && !CameraWithinTolerance(truth).value_or(true)) {
        status += " (outside tolerance against the truth)";
      }
      const std::optional<double>& direction =
          open_axis ? t.across_axis_direction_error_deg : t.translation_direction_error_deg;
      std::snprintf(line, sizeof(line), "%-10s %-10s %10s %10s %10s %10s %8d  ",
                    m == 0 ? r.rig.cameras[c].name.c_str() : "", r.semantic_mode.c_str(),
                    Opt(t.rotation_error_deg, "%.3f deg").c_str(), Opt(direction, "%.2f deg").c_str(),
                    Opt(st.direction_std_deg, "%.3f deg").c_str(), Opt(t.position_error_m, "%.3f m").c_str(),
                    st.observations);
      out << line << status << "\n";
    }
  }
  return out.str();
}

std::string FormatRigSummary(const CalibrationRun& run) {
  std::ostringstream out;
  for (size_t m = 0; m < run.results.size(); ++m) {
    const RigCalibrationResult& r = run.results[m];
    const CalibrationScores* truth = run.Truth(m);
    int calibrated = 0, if_synchronised = 0;
    std::optional<double> worst_rot, worst_dir, worst_across;
    // Over every camera with an estimate, "rotation only" ones included, as evaluation.json's summary,
    // but the reference, whose error is 0 by definition: with it alone placed there is no error.
    for (size_t c = 0; c < r.camera_stats.size(); ++c) {
      if (truth && c > 0) {
        const CameraAgainstTruth& t = truth->cameras[c];
        if (t.rotation_error_deg) worst_rot = std::max(worst_rot.value_or(0.0), *t.rotation_error_deg);
        if (t.translation_direction_error_deg) worst_dir = std::max(worst_dir.value_or(0.0), *t.translation_direction_error_deg);
        if (t.across_axis_direction_error_deg) {
          worst_across = std::max(worst_across.value_or(0.0), *t.across_axis_direction_error_deg);
        }
      }
      calibrated += r.rig.cameras[c].cam_from_rig.has_value();
      if_synchronised += r.camera_status[c].outcome == CameraOutcome::kCalibratedIfSynchronised;
    }
    out << r.semantic_mode << ": " << calibrated << "/" << r.rig.cameras.size() << " cameras calibrated";
    if (if_synchronised > 0) out << " (" << if_synchronised << " if synchronised)";
    if (truth) {
      out << ", worst rotation error " << Opt(worst_rot, "%.4f deg") << ", worst translation direction error "
          << Opt(worst_dir, "%.2f deg");
      if (worst_across) out << ", worst direction across an open axis " << Opt(worst_across, "%.2f deg");
    }
    if (r.num_observations > 0) {
      out << ", reprojection RMS " << Fmt("%.2f px", r.reprojection_rms_px) << " over " << r.num_observations
          << " observations";
      // The stated deviations count the residual coordinates the points take up, and the residuals
      // of one image region as moving together.
      if (r.residual_correlation > 1.1) {
        out << " (residuals counted over what the fit leaves free and by image region: deviations x"
            << Fmt("%.1f", std::sqrt(r.residual_correlation)) << ")";
      }
      out << "; ";
    } else {
      out << ", no bundle adjustment (no camera joined " << (r.rig.cameras.empty() ? "" : r.rig.cameras[0].name)
          << "); ";
    }
    out << ScaleText(r) << "\n";
    for (const std::string& w : r.warnings) out << "  warning: " << w << "\n";
  }
  return out.str();
}

std::string FormatTimeTable(const CalibrationRun& run) {
  const std::vector<RigCalibrationResult>& results = run.results;
  const CaptureTimeOptions& o = run.options.rig.capture_time;
  auto timed = [](const RigCameraStats& st) { return st.time_offset_s.has_value() || st.readout_s.has_value(); };
  bool any = false;
  for (const RigCalibrationResult& r : results) any = any || std::any_of(r.camera_stats.begin(), r.camera_stats.end(), timed);
  if (!any) return "";
  std::ostringstream out;
  char line[512];
  std::snprintf(line, sizeof(line), "%-10s %-10s %20s %20s %11s %11s  %s\n", "camera", "method", "time_offset",
                "readout", "offset_err", "readout_err", "found by");
  out << line;
  auto with_std = [](const std::optional<double>& v, const std::optional<double>& s) -> std::string {
    if (!v) return "-";
    return Fmt("%+.2f", 1000.0 * *v) + (s ? PlusMinus(1000.0 * *s, 2) : std::string()) + " ms";
  };
  for (size_t c = 0; c < results[0].rig.cameras.size(); ++c) {
    for (size_t m = 0; m < results.size(); ++m) {
      const RigCalibrationResult& r = results[m];
      const RigCameraStats& st = r.camera_stats[c];
      if (!timed(st)) continue;
      const CalibrationScores* scores = run.Truth(m);
      const CameraAgainstTruth* t = scores ? &scores->cameras[c] : nullptr;
      const std::string offset = c == 0 && o.estimate_offsets ? "0 (reference)"
                                 : st.time_offset_undetermined ? "not determined"
                                                               : with_std(st.time_offset_s, st.time_offset_stddev_s);
      const char* how = o.estimate_offsets || o.estimate_readout ? "estimated in the bundle adjustment"
                                                                 : "measured by the synchronisation check";
      auto ms = [](const std::optional<double>& v) { return v ? Fmt("%.2f ms", 1000.0 * std::abs(*v)) : std::string("-"); };
      std::snprintf(line, sizeof(line), "%-10s %-10s %20s %20s %11s %11s  %s\n", r.rig.cameras[c].name.c_str(),
                    r.semantic_mode.c_str(), offset.c_str(), with_std(st.readout_s, st.readout_stddev_s).c_str(),
                    ms(t ? t->time_offset_error_s : std::nullopt).c_str(), ms(t ? t->readout_error_s : std::nullopt).c_str(),
                    how);
      out << line;
    }
  }
  return out.str();
}

std::string FormatIntrinsicsTable(const CalibrationRun& run) {
  const std::vector<RigCalibrationResult>& results = run.results;
  std::ostringstream out;
  char line[512];
  std::snprintf(line, sizeof(line), "%-10s %-10s %18s %18s %16s %16s %10s %10s\n", "camera", "method", "fx change",
                "fy change", "cx change", "cy change", "focal_err", "pp_err");
  out << line;
  if (results.empty()) return out.str();
  for (size_t c = 0; c < results[0].rig.cameras.size(); ++c) {
    for (size_t m = 0; m < results.size(); ++m) {
      const RigCalibrationResult& r = results[m];
      const std::optional<RefinedIntrinsics>& in = r.camera_stats[c].intrinsics;
      const CalibrationScores* scores = run.Truth(m);
      const IntrinsicsErrors* errors = scores && scores->cameras[c].intrinsics ? &*scores->cameras[c].intrinsics : nullptr;
      const char* name = m == 0 ? r.rig.cameras[c].name.c_str() : "";
      if (!in || in->given.size() < 4 || in->refined.size() < 4) {
        std::snprintf(line, sizeof(line), "%-10s %-10s not refined (no bundle-adjustment observation)\n", name,
                      r.semantic_mode.c_str());
        out << line;
        continue;
      }
      auto stddev = [&](size_t i) { return i < in->stddev.size() ? in->stddev[i] : std::nan(""); };
      auto focal = [&](size_t i) {
        return Fmt("%+.3f", 100.0 * (in->refined[i] / in->given[i] - 1.0)) + PlusMinus(100.0 * stddev(i) / in->given[i], 3) + "%";
      };
      auto pp = [&](size_t i) { return Fmt("%+.2f", in->refined[i] - in->given[i]) + PlusMinus(stddev(i), 2) + " px"; };
      std::snprintf(line, sizeof(line), "%-10s %-10s %18s %18s %16s %16s %10s %10s\n", name, r.semantic_mode.c_str(),
                    focal(0).c_str(), focal(1).c_str(), pp(2).c_str(), pp(3).c_str(),
                    errors ? Fmt("%.3f%%", errors->focal_error_percent).c_str() : "-",
                    errors ? Fmt("%.2f px", errors->principal_point_error_px).c_str() : "-");
      out << line;
    }
  }
  return out.str();
}

}  // namespace rigsim
