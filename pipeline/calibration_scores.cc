#include "pipeline/calibration_scores.h"

#include <algorithm>
#include <stdexcept>

#include <tbb/parallel_for.h>

#include "dataset/capture_poses.h"
#include "dataset/image_io.h"
#include "dataset/label_image.h"
#include "evaluation/pose_errors.h"
#include "evaluation/rig_scores.h"
#include "evaluation/verdicts.h"

namespace rigsim {
namespace {

// Per match of `matches`, whether it is one of `inliers`, which hold a subsequence of them in order.
std::vector<char> InlierFlags(const std::vector<std::pair<int, int>>& matches,
                              const std::vector<std::pair<int, int>>& inliers) {
  std::vector<char> flags(matches.size(), 0);
  size_t next = 0;
  for (size_t i = 0; i < matches.size() && next < inliers.size(); ++i) {
    if (matches[i] == inliers[next]) {
      flags[i] = 1;
      ++next;
    }
  }
  return flags;
}

// The true relative pose of two cameras as a pair pooled over the frames sees it: fixed when both
// capture at their frames' times; otherwise the mean over the frames of B's pose (at its middle
// row's time) from A's, which the rig's motion between their captures changes.
Rigid3d TrueRelativePose(const RigCamera& a, const RigCamera& b, const FramesFile& frames) {
  const Rigid3d fixed = *b.cam_from_rig * a.cam_from_rig->Inverse();
  if ((!CapturePoses::IsTimed(a) && !CapturePoses::IsTimed(b)) || frames.frames.empty()) return fixed;
  const CapturePoses poses({a, b}, frames);
  const auto middle = [](const RigCamera& c) { return c.RowTime(c.camera.height() / 2); };
  std::vector<Rigid3d> b_from_a;
  for (const Frame& f : frames.frames) {
    b_from_a.push_back(poses.CamFromWorld(b, f, f.timestamp_s + middle(b)) *
                       poses.CamFromWorld(a, f, f.timestamp_s + middle(a)).Inverse());
  }
  return MeanOfNearbyPoses(b_from_a);
}

}  // namespace

CalibrationScores ScorePoses(const Rig& truth, const FramesFile& frames, const RigCalibrationResult& result) {
  CalibrationScores s;
  for (const PairResult& pr : result.pairwise.pairs) {
    const int a = truth.FindCamera(pr.cam_a), b = truth.FindCamera(pr.cam_b);
    if (a < 0 || b < 0) throw std::invalid_argument("ScorePoses: pair " + pr.cam_a + "-" + pr.cam_b + " not in the truth");
    PairAgainstTruth p;
    p.cam_b_from_cam_a = TrueRelativePose(truth.cameras[a], truth.cameras[b], frames);
    if (pr.two_view.success) {
      p.rotation_error_deg = RotationErrorDeg(pr.two_view.cam_b_from_cam_a, p.cam_b_from_cam_a);
      p.translation_direction_error_deg = TranslationDirectionErrorDeg(pr.two_view.cam_b_from_cam_a, p.cam_b_from_cam_a);
    }
    s.pairs.push_back(p);
  }
  const std::vector<CameraErrors> errors = CalibrationCameraErrors(truth, RigEstimateOf(result));
  for (size_t c = 0; c < errors.size(); ++c) {
    CameraAgainstTruth cam;
    cam.rotation_error_deg = errors[c].rotation_error_deg;
    cam.translation_direction_error_deg = errors[c].direction_error_deg;
    cam.position_error_m = errors[c].position_error_m;
    cam.across_axis_direction_error_deg = errors[c].across_axis_direction_error_deg;
    if (const auto& in = result.camera_stats.at(c).intrinsics) {
      cam.intrinsics = ScoreIntrinsics(in->given, in->refined, truth.cameras[c].camera);
    }
    const RigCameraStats& stats = result.camera_stats.at(c);
    if (stats.time_offset_s) {
      cam.time_offset_error_s = *stats.time_offset_s - (truth.cameras[c].time_offset_s - truth.cameras[0].time_offset_s);
    }
    if (stats.readout_s) cam.readout_error_s = *stats.readout_s - truth.cameras[c].readout_s;
    // Camera 0 is the gauge (its errors are 0 by construction); a pose that holds if synchronised is
    // judged only where the truth's camera is.
    const bool condition_holds = result.camera_status.at(c).outcome != CameraOutcome::kCalibratedIfSynchronised ||
                                 CapturesWithReference(truth, c);
    if (c > 0 && condition_holds) {
      const StatedError rotation{cam.rotation_error_deg, stats.rotation_std_deg};
      const StatedError direction{result.rig.cameras[c].cam_from_rig ? cam.translation_direction_error_deg : std::nullopt,
                                  stats.direction_std_deg};
      cam.rotation_sd_ratio = rotation.Ratio();
      cam.direction_sd_ratio = direction.Ratio();
      cam.overconfident = Overconfident({rotation, direction});
    }
    s.cameras.push_back(cam);
  }
  return s;
}

void ScoreMatches(const std::filesystem::path& dataset_dir, const Rig& truth, const FramesFile& frames,
                  const std::vector<RigCalibrationResult>& results, const std::vector<PairwiseMatchData>& matches,
                  const MatchPrecisionOptions& options, std::vector<CalibrationScores>* scores) {
  const DatasetLayout layout(dataset_dir);
  const int num_cams = static_cast<int>(truth.cameras.size());
  const int num_frames = static_cast<int>(frames.frames.size());
  const int num_modes = static_cast<int>(results.size());
  const auto image = [&](int c, int f) { return c * num_frames + f; };
  std::vector<char> have_depth(num_cams * num_frames, 0);
  for (int c = 0; c < num_cams; ++c) {
    for (int f = 0; f < num_frames; ++f) {
      have_depth[image(c, f)] = std::filesystem::exists(layout.Depth(truth.cameras[c].name, frames.frames[f].name));
    }
  }
  if (std::none_of(have_depth.begin(), have_depth.end(), [](char c) { return c != 0; })) return;
  const CapturePoses capture_poses(truth.cameras, frames);  // every view at its capture time

  struct Counts {
    MatchPrecisionCounts all, inliers;
    bool evaluated = false;
    bool labelled = false;  // both label images known
  };
  // Per (frame, mode, pair).
  std::vector<int> first_pair(num_modes + 1, 0);
  for (int m = 0; m < num_modes; ++m) {
    first_pair[m + 1] = first_pair[m] + static_cast<int>(results[m].pairwise.pairs.size());
    (*scores)[m].match_correct.assign(results[m].pairwise.pairs.size(), std::vector<std::vector<char>>(num_frames));
  }
  const int num_mp = first_pair[num_modes];
  std::vector<Counts> counts(num_frames * num_mp);
  tbb::parallel_for(0, num_frames, [&](int f) {
    std::vector<ImageF> range(num_cams);
    std::vector<ImageU8> labels(num_cams);  // the true labels: what a cross-class match is
    std::vector<ViewPose> pose(num_cams);
    for (int c = 0; c < num_cams; ++c) {
      if (!have_depth[image(c, f)]) continue;
      pose[c] = capture_poses.Of(truth.cameras[c], frames.frames[f]);
      const Camera& camera = truth.cameras[c].RenderedCamera();  // the lens the range images were made through
      const auto path = layout.Depth(truth.cameras[c].name, frames.frames[f].name);
      range[c] = ReadImageF(path);
      if (!range[c].SameSize(camera.width(), camera.height()) || range[c].channels != 1) {
        throw std::runtime_error(path.string() + ": range image must be 1 channel of the camera's size");
      }
      const auto label_path = layout.Label(truth.cameras[c].name, frames.frames[f].name);
      if (std::filesystem::exists(label_path)) labels[c] = ReadLabelImage(label_path, camera.width(), camera.height());
    }
    for (int m = 0; m < num_modes; ++m) {
      const PairwiseMatchData& md = matches[m];
      for (size_t p = 0; p < results[m].pairwise.pairs.size(); ++p) {
        const PairResult& pr = results[m].pairwise.pairs[p];
        const int a = truth.FindCamera(pr.cam_a), b = truth.FindCamera(pr.cam_b);
        if (range[a].empty() || range[b].empty()) continue;
        const std::vector<std::pair<int, int>>& mt = md.matches[p][f];
        std::vector<Eigen::Vector2d> pa, pb;
        for (const auto& [ka, kb] : mt) {
          pa.push_back(md.keypoints[f][a][ka]);
          pb.push_back(md.keypoints[f][b][kb]);
        }
        Counts& cnt = counts[f * num_mp + first_pair[m] + p];
        int at_infinity = 0;
        const std::vector<char> ok = CheckMatches(pa, pb, truth.cameras[a].RenderedCamera(), range[a], pose[a],
                                                  truth.cameras[b].RenderedCamera(), range[b], pose[b], options,
                                                  &at_infinity);
        (*scores)[m].match_correct[p][f] = ok;
        cnt.evaluated = true;
        cnt.all.evaluated = static_cast<int>(mt.size());
        cnt.all.at_infinity = at_infinity;
        cnt.labelled = !labels[a].empty() && !labels[b].empty();
        const std::vector<char> cross = cnt.labelled ? CrossClassMatches(pa, pb, labels[a], labels[b])
                                                     : std::vector<char>(mt.size(), 0);
        const std::vector<char> inlier = InlierFlags(mt, md.inliers[p][f]);
        for (size_t i = 0; i < mt.size(); ++i) {
          cnt.all.correct += ok[i];
          cnt.all.cross_class += cross[i];
          cnt.all.cross_class_correct += cross[i] && ok[i];
          if (inlier[i]) {
            ++cnt.inliers.evaluated;
            cnt.inliers.correct += ok[i];
          }
        }
      }
    }
  });
  for (int m = 0; m < num_modes; ++m) {
    const RigCalibrationResult& r = results[m];
    // Pairs the rig estimated again have other inliers than those checked here.
    const bool reestimated = r.reestimated_pairs.size() == r.pairwise.pairs.size() && !r.reestimated_pairs.empty();
    for (size_t p = 0; p < r.pairwise.pairs.size(); ++p) {
      MatchPrecisionCounts all, inl;
      bool any = false, labelled = true;
      for (int f = 0; f < num_frames; ++f) {
        const Counts& cnt = counts[f * num_mp + first_pair[m] + p];
        any = any || cnt.evaluated;
        labelled = labelled && (!cnt.evaluated || cnt.labelled);
        all += cnt.all;
        inl += cnt.inliers;
      }
      if (!any) continue;
      PairAgainstTruth& pt = (*scores)[m].pairs[p];
      pt.matches_evaluated = all.evaluated;
      pt.matches_correct = all.correct;
      pt.matches_at_infinity = all.at_infinity;
      if (labelled) {
        pt.cross_class_matches = all.cross_class;
        pt.cross_class_correct = all.cross_class_correct;
      }
      if (all.evaluated > 0) pt.match_precision = all.Precision();
      if (reestimated) continue;
      pt.inliers_evaluated = inl.evaluated;
      pt.inliers_correct = inl.correct;
      if (inl.evaluated > 0) pt.inlier_precision = inl.Precision();
    }
  }
}

std::optional<double> PooledMatchPrecision::Precision() const {
  return evaluated > 0 ? std::optional<double>(double(correct) / evaluated) : std::nullopt;
}

PooledMatchPrecision PoolMatchPrecision(const CalibrationScores& scores) {
  PooledMatchPrecision out;
  for (const PairAgainstTruth& p : scores.pairs) {
    out.evaluated += p.matches_evaluated;
    out.correct += p.matches_correct;
    if (p.cross_class_matches) {
      out.cross_class = out.cross_class.value_or(0) + *p.cross_class_matches;
      out.cross_class_correct += p.cross_class_correct;
    }
  }
  return out;
}

std::vector<signed char> InlierVerdicts(const CalibrationScores& scores, const PairwiseMatchData& matches, int pair,
                                        int frame) {
  if (pair < 0 || size_t(pair) >= scores.match_correct.size()) return {};
  const std::vector<char>& correct = scores.match_correct[pair].at(frame);
  if (correct.empty()) return {};
  const std::vector<char> inlier = InlierFlags(matches.matches[pair][frame], matches.inliers[pair][frame]);
  std::vector<signed char> out;
  for (size_t i = 0; i < inlier.size(); ++i) {
    if (inlier[i]) out.push_back(correct[i]);
  }
  return out;
}

std::optional<bool> PairWithinTolerance(const PairResult& pair, const PairAgainstTruth* truth) {
  if (!truth) return std::nullopt;
  if (!pair.two_view.success) return false;
  return WithinTolerance(truth->rotation_error_deg,
                         pair.two_view.rotation_only ? std::nullopt : truth->translation_direction_error_deg,
                         kPairTolerance);
}

std::optional<bool> CameraWithinTolerance(const CameraAgainstTruth* truth) {
  if (!truth) return std::nullopt;
  if (!truth->rotation_error_deg) return false;  // no estimate
  const std::optional<double>& direction = truth->translation_direction_error_deg
                                               ? truth->translation_direction_error_deg
                                               : truth->across_axis_direction_error_deg;
  return WithinTolerance(truth->rotation_error_deg, direction, kCameraTolerance);
}

RigEstimate RigEstimateOf(const RigCalibrationResult& r) {
  RigEstimate e;
  e.method = r.semantic_mode;
  e.metric = r.scale_kind == ScaleKind::kMetric;
  for (size_t c = 0; c < r.rig.cameras.size(); ++c) {
    e.cam_from_rig.push_back(r.rig.cameras[c].cam_from_rig);
    const RigCameraStats* stats = c < r.camera_stats.size() ? &r.camera_stats[c] : nullptr;
    e.rotation_std_deg.push_back(stats ? stats->rotation_std_deg : std::nullopt);
    e.direction_std_deg.push_back(stats ? stats->direction_std_deg : std::nullopt);
    e.if_synchronised.push_back(c < r.camera_status.size() &&
                                r.camera_status[c].outcome == CameraOutcome::kCalibratedIfSynchronised);
    const bool rotation_only = !r.rig.cameras[c].cam_from_rig && c < r.cam_from_rig_rotation.size();
    e.rotation_only.push_back(rotation_only ? r.cam_from_rig_rotation[c] : std::nullopt);
    const bool open_axis = rotation_only && e.rotation_only.back() && c < r.open_axis.size() && r.open_axis[c] &&
                           c < r.partial_centre.size() && r.partial_centre[c];
    e.open_axis.push_back(open_axis ? std::optional<OpenAxisCentre>({*r.open_axis[c], *r.partial_centre[c]})
                                    : std::nullopt);
  }
  return e;
}

}  // namespace rigsim
