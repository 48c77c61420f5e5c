#include "calibrator/pipeline.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <stdexcept>

#include <opencv2/core.hpp>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>

#include "dataset/dataset.h"
#include "dataset/image_io.h"
#include "dataset/label_image.h"
#include "geometry/rig.h"

namespace rigsim {
namespace {

using Clock = std::chrono::steady_clock;
double Seconds(Clock::time_point since) { return std::chrono::duration<double>(Clock::now() - since).count(); }

// Feature kinds shared between modes: none/gated detect everywhere, mask/mask+gated on the mask.
constexpr int kUnmasked = 0;
constexpr int kMasked = 1;
int FeatureKind(SemanticMode m) { return UsesMask(m) ? kMasked : kUnmasked; }

// OpenCV parallelises inside SIFT; with TBB running one image per worker that would
// oversubscribe the cores. Restores the previous setting on exit.
class OpenCvSingleThread {
 public:
  OpenCvSingleThread() : previous_(cv::getNumThreads()) { cv::setNumThreads(1); }
  ~OpenCvSingleThread() { cv::setNumThreads(previous_); }

 private:
  int previous_;
};

struct PairIndex {
  int a, b;
};

// Matches of one (mode, pair), pooled over frames in frame order.
struct PooledMatches {
  std::vector<Eigen::Vector2d> px_a, px_b;
  std::vector<int> frame_begin;  // offset of each frame's matches; frame_begin[num_frames] = size
};

}  // namespace

void CalibrationOptions::Check() const {
  features.Check();
  matching.Check();
  two_view.Check();
  precision.Check();
  labels.Check();
  if (num_threads < 0) throw std::invalid_argument("CalibrationOptions: num_threads must be >= 0");
  if (screen_features < 0) throw std::invalid_argument("CalibrationOptions: screen_features must be >= 0");
}

CalibrationReport CalibrateDatasetPairs(const std::filesystem::path& dataset_dir, const CalibrationOptions& options) {
  return CalibrateDatasetPairs(dataset_dir, options, {options.semantic_mode}).front();
}

std::vector<CalibrationReport> CalibrateDatasetPairs(const std::filesystem::path& dataset_dir,
                                                     const CalibrationOptions& options,
                                                     const std::vector<SemanticMode>& modes,
                                                     std::vector<PairwiseMatchData>* match_data) {
  options.Check();
  if (modes.empty()) throw std::invalid_argument("CalibrateDatasetPairs: no semantic mode given");
  const DatasetLayout layout(dataset_dir);
  const Rig rig = ReadRig(layout.RigJson());
  const int num_cams = static_cast<int>(rig.cameras.size());
  if (num_cams < 2) throw std::runtime_error(layout.RigJson().string() + ": calibration needs at least 2 cameras");
  const FramesFile frames_file = layout.ReadFramesOrScan(rig.cameras[0].name);
  const int num_frames = static_cast<int>(frames_file.frames.size());
  if (num_frames == 0) throw std::runtime_error(dataset_dir.string() + ": no frames found");

  bool need_kind[2] = {false, false};
  bool need_labels = false;
  for (SemanticMode m : modes) {
    need_kind[FeatureKind(m)] = true;
    need_labels = need_labels || NeedsLabels(m);
  }

  std::unique_ptr<tbb::global_control> thread_limit;
  if (options.num_threads > 0) {
    thread_limit = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism,
                                                         static_cast<size_t>(options.num_threads));
  }
  const OpenCvSingleThread opencv_single_thread;

  // 0. Every photo is there and has its camera's size, read from the file headers before any is
  //    decoded: a missing or wrong photo stops the run at once, not after minutes of detection.
  const int num_images = num_cams * num_frames;
  auto image_index = [&](int cam, int frame) { return cam * num_frames + frame; };
  std::vector<std::filesystem::path> image_paths(num_images);
  for (int cam = 0; cam < num_cams; ++cam) {
    const RigCamera& rc = rig.cameras[cam];
    for (int frame = 0; frame < num_frames; ++frame) {
      const std::filesystem::path path = layout.RequireImage(rc.name, frames_file.frames[frame].name);
      const ImageSize size = ReadImageSize(path);
      const int w = rc.camera.width(), h = rc.camera.height();
      if (size.width != w || size.height != h) {
        throw std::runtime_error(path.string() + ": image is " + std::to_string(size.width) + "x" +
                                 std::to_string(size.height) + ", camera '" + rc.name + "' is " + std::to_string(w) +
                                 "x" + std::to_string(h));
      }
      image_paths[image_index(cam, frame)] = path;
    }
  }

  // 1. Features: one task per image; each image (and its labels) is read once for all kinds.
  std::vector<FeatureSet> features[2];
  std::vector<double> detect_time[2];
  for (int k = 0; k < 2; ++k) {
    if (need_kind[k]) {
      features[k].resize(num_images);
      detect_time[k].assign(num_images, 0.0);
    }
  }
  tbb::parallel_for(0, num_images, [&](int idx) {
    const int cam = idx / num_frames, frame = idx % num_frames;
    const RigCamera& rc = rig.cameras[cam];
    const std::string& frame_name = frames_file.frames[frame].name;
    const ImageU8 rgb = ReadImageU8(image_paths[idx], 3);
    const int w = rc.camera.width(), h = rc.camera.height();
    ImageU8 labels;
    // Checks size and Cityscapes ids or colours; names the file.
    if (need_labels) labels = LoadLabels(options.labels, layout, rc.name, frame_name, w, h);
    for (int k = 0; k < 2; ++k) {
      if (!need_kind[k]) continue;
      const auto start = Clock::now();
      features[k][idx] = DetectFeatures(rgb, need_labels ? &labels : nullptr, options.features,
                                        k == kMasked ? &options.reliable : nullptr);
      detect_time[k][idx] = Seconds(start);
    }
  });

  // 2. Matches per (mode, pair, frame).
  std::vector<PairIndex> pairs;
  for (int a = 0; a < num_cams; ++a) {
    for (int b = a + 1; b < num_cams; ++b) pairs.push_back({a, b});
  }
  const int num_modes = static_cast<int>(modes.size());
  const int num_pairs = static_cast<int>(pairs.size());
  auto job_index = [&](int m, int p, int f) { return (m * num_pairs + p) * num_frames + f; };

  // 2a. Screening (CalibrationOptions::screen_features): which (mode, pair)s are worth matching.
  std::vector<std::string> screened_out(num_modes * num_pairs);  // reason; empty = match in full
  std::vector<double> screen_time(num_modes * num_pairs, 0.0);
  if (options.screen_features > 0) {
    std::vector<int> screen_frames = {0};
    if (num_frames / 2 > 0) screen_frames.push_back(num_frames / 2);
    tbb::parallel_for(0, num_modes * num_pairs, [&](int mp) {
      const int m = mp / num_pairs, p = mp % num_pairs;
      const auto start = Clock::now();
      MatchOptions mo = options.matching;
      mo.gate_by_class = UsesGating(modes[m]);
      const auto& feats = features[FeatureKind(modes[m])];
      std::vector<Eigen::Vector2d> px_a, px_b;
      for (int f : screen_frames) {
        const FeatureSet fa = feats[image_index(pairs[p].a, f)].Head(options.screen_features);
        const FeatureSet fb = feats[image_index(pairs[p].b, f)].Head(options.screen_features);
        for (const Match& mt : MatchFeatures(fa, fb, mo)) {
          px_a.push_back(fa.keypoints[mt.a].px);
          px_b.push_back(fb.keypoints[mt.b].px);
        }
      }
      const TwoViewResult tv =
          EstimateRelativePose(rig.cameras[pairs[p].a].camera, px_a, rig.cameras[pairs[p].b].camera, px_b, options.two_view);
      if (!tv.success) {
        screened_out[mp] = "screened out (no shared view found among the " + std::to_string(options.screen_features) +
                           " strongest keypoints of " + std::to_string(screen_frames.size()) + " frame(s): " +
                           tv.failure_reason + ")";
      }
      screen_time[mp] = Seconds(start);
    });
  }

  // 2b. Full matching of the pairs that passed.
  const int num_jobs = num_modes * num_pairs * num_frames;
  std::vector<std::vector<Match>> matches(num_jobs);
  std::vector<MatchStats> match_stats(num_jobs);
  tbb::parallel_for(0, num_jobs, [&](int job) {
    const int f = job % num_frames;
    const int p = (job / num_frames) % num_pairs;
    const int m = job / (num_frames * num_pairs);
    if (!screened_out[m * num_pairs + p].empty()) return;
    MatchOptions mo = options.matching;
    mo.gate_by_class = UsesGating(modes[m]);
    const auto& feats = features[FeatureKind(modes[m])];
    matches[job] = MatchFeatures(feats[image_index(pairs[p].a, f)], feats[image_index(pairs[p].b, f)], mo,
                                 &match_stats[job]);
  });

  // 3. Pool the frames of each (mode, pair); one two-view estimate each.
  std::vector<PooledMatches> pooled(num_modes * num_pairs);
  std::vector<TwoViewResult> two_view(num_modes * num_pairs);
  std::vector<double> pose_time(num_modes * num_pairs, 0.0);
  tbb::parallel_for(0, num_modes * num_pairs, [&](int mp) {
    const int m = mp / num_pairs, p = mp % num_pairs;
    const auto& feats = features[FeatureKind(modes[m])];
    PooledMatches& pm = pooled[mp];
    for (int f = 0; f < num_frames; ++f) {
      pm.frame_begin.push_back(static_cast<int>(pm.px_a.size()));
      const FeatureSet& fa = feats[image_index(pairs[p].a, f)];
      const FeatureSet& fb = feats[image_index(pairs[p].b, f)];
      for (const Match& mt : matches[job_index(m, p, f)]) {
        pm.px_a.push_back(fa.keypoints[mt.a].px);
        pm.px_b.push_back(fb.keypoints[mt.b].px);
      }
    }
    pm.frame_begin.push_back(static_cast<int>(pm.px_a.size()));
    if (!screened_out[mp].empty()) {
      two_view[mp].failure_reason = screened_out[mp];
      return;
    }
    const auto start = Clock::now();
    two_view[mp] = EstimateRelativePose(rig.cameras[pairs[p].a].camera, pm.px_a, rig.cameras[pairs[p].b].camera,
                                        pm.px_b, options.two_view);
    pose_time[mp] = Seconds(start);
  });

  // 4. Reports.
  std::vector<CalibrationReport> reports(num_modes);
  for (int m = 0; m < num_modes; ++m) {
    CalibrationReport& rep = reports[m];
    rep.semantic_mode = std::string(SemanticModeName(modes[m]));
    rep.num_cameras = num_cams;
    rep.num_frames = num_frames;
    const int kind = FeatureKind(modes[m]);
    double keypoints = 0.0;
    for (int i = 0; i < num_images; ++i) {
      keypoints += features[kind][i].size();
      rep.detect_time_s += detect_time[kind][i];
    }
    rep.mean_keypoints_per_image = keypoints / num_images;
    for (int p = 0; p < num_pairs; ++p) {
      const int mp = m * num_pairs + p;
      const TwoViewResult& tv = two_view[mp];
      PairResult pr;
      pr.cam_a = rig.cameras[pairs[p].a].name;
      pr.cam_b = rig.cameras[pairs[p].b].name;
      pr.frames = num_frames;
      pr.matches = static_cast<int>(pooled[mp].px_a.size());
      pr.inliers = tv.num_inliers;
      pr.success = tv.success;
      pr.rotation_only = tv.rotation_only;
      pr.pair_type = tv.pair_type;
      pr.homography_inliers = tv.num_homography_inliers;
      pr.failure_reason = tv.failure_reason;
      pr.cam_b_from_cam_a = tv.cam_b_from_cam_a;
      pr.median_residual_deg = tv.median_residual_deg;
      for (int f = 0; f < num_frames; ++f) {
        const MatchStats& s = match_stats[job_index(m, p, f)];
        pr.distance_evaluations += s.distance_evaluations;
        pr.match_time_s += s.time_s;
      }
      pr.pose_time_s = pose_time[mp];
      pr.screen_time_s = screen_time[mp];
      rep.screen_time_s += pr.screen_time_s;
      rep.match_time_s += pr.match_time_s;
      rep.pose_time_s += pr.pose_time_s;
      rep.pairs.push_back(std::move(pr));
    }
  }

  if (match_data) {
    match_data->assign(num_modes, {});
    for (int m = 0; m < num_modes; ++m) {
      PairwiseMatchData& md = (*match_data)[m];
      const auto& feats = features[FeatureKind(modes[m])];
      md.keypoints.assign(num_frames, std::vector<std::vector<Eigen::Vector2d>>(num_cams));
      for (int f = 0; f < num_frames; ++f) {
        for (int c = 0; c < num_cams; ++c) {
          for (const Keypoint& kp : feats[image_index(c, f)].keypoints) md.keypoints[f][c].push_back(kp.px);
        }
      }
      md.inliers.assign(num_pairs, std::vector<std::vector<std::pair<int, int>>>(num_frames));
      for (int p = 0; p < num_pairs; ++p) {
        const int mp = m * num_pairs + p;
        if (!two_view[mp].success) continue;
        for (int f = 0; f < num_frames; ++f) {
          const std::vector<Match>& mt = matches[job_index(m, p, f)];
          for (size_t i = 0; i < mt.size(); ++i) {
            if (two_view[mp].inlier_mask[pooled[mp].frame_begin[f] + i]) md.inliers[p][f].push_back({mt[i].a, mt[i].b});
          }
        }
      }
    }
  }

  // 4b. Temporal pairs: each camera with itself between consecutive frames, per mode.
  if (match_data && options.temporal_matches && num_frames >= 2) {
    const int steps = num_frames - 1;
    const int num_temporal = num_modes * num_cams * steps;
    std::vector<TemporalPairEstimate> temporal(num_temporal);
    std::vector<double> t_match(num_temporal, 0.0), t_pose(num_temporal, 0.0);
    tbb::parallel_for(0, num_temporal, [&](int job) {
      const int k = job % steps;
      const int c = (job / steps) % num_cams;
      const int m = job / (steps * num_cams);
      MatchOptions mo = options.matching;
      mo.gate_by_class = UsesGating(modes[m]);
      const auto& feats = features[FeatureKind(modes[m])];
      const FeatureSet& fa = feats[image_index(c, k)];
      const FeatureSet& fb = feats[image_index(c, k + 1)];
      MatchStats stats;
      const std::vector<Match> mt = MatchFeatures(fa, fb, mo, &stats);
      t_match[job] = stats.time_s;
      std::vector<Eigen::Vector2d> pa, pb;
      for (const Match& x : mt) {
        pa.push_back(fa.keypoints[x.a].px);
        pb.push_back(fb.keypoints[x.b].px);
      }
      const auto start = Clock::now();
      const TwoViewResult tv = EstimateRelativePose(rig.cameras[c].camera, pa, rig.cameras[c].camera, pb, options.two_view);
      t_pose[job] = Seconds(start);
      TemporalPairEstimate& te = temporal[job];
      te.camera = c;
      te.frame = k;
      te.estimate.cam_a = c;
      te.estimate.cam_b = c;
      te.estimate.success = tv.success;
      te.estimate.rotation_only = tv.rotation_only;
      te.estimate.cam_b_from_cam_a = tv.cam_b_from_cam_a;
      te.estimate.num_inliers = tv.num_inliers;
      te.estimate.failure_reason = tv.failure_reason;
      if (tv.success) {
        for (size_t i = 0; i < mt.size(); ++i) {
          if (tv.inlier_mask[i]) te.inliers.push_back({mt[i].a, mt[i].b});
        }
      }
    });
    for (int m = 0; m < num_modes; ++m) {
      for (int i = 0; i < num_cams * steps; ++i) {
        const int job = m * num_cams * steps + i;
        reports[m].temporal_match_time_s += t_match[job];
        reports[m].temporal_pose_time_s += t_pose[job];
        (*match_data)[m].temporal.push_back(std::move(temporal[job]));
      }
    }
  }

  if (!options.evaluate || !rig.HasAllPoses()) return reports;

  // 5. Ground truth: pose errors per pair, match precision per frame where depth exists.
  for (int m = 0; m < num_modes; ++m) {
    for (int p = 0; p < num_pairs; ++p) {
      PairResult& pr = reports[m].pairs[p];
      const Rigid3d gt = *rig.cameras[pairs[p].b].cam_from_rig * rig.cameras[pairs[p].a].cam_from_rig->Inverse();
      pr.cam_b_from_cam_a_gt = gt;
      if (pr.success) {
        pr.rotation_error_deg = RotationErrorDeg(pr.cam_b_from_cam_a, gt);
        pr.translation_direction_error_deg = TranslationDirectionErrorDeg(pr.cam_b_from_cam_a, gt);
      }
    }
  }
  std::vector<char> have_depth(num_images, 0);
  for (int c = 0; c < num_cams; ++c) {
    for (int f = 0; f < num_frames; ++f) {
      have_depth[image_index(c, f)] =
          std::filesystem::exists(layout.Depth(rig.cameras[c].name, frames_file.frames[f].name));
    }
  }
  if (std::none_of(have_depth.begin(), have_depth.end(), [](char c) { return c != 0; })) return reports;

  // Per frame: read each camera's range image once, evaluate every mode and pair of that frame.
  struct Counts {
    MatchPrecisionCounts all, inliers;
    bool evaluated = false;
  };
  std::vector<Counts> counts(num_frames * num_modes * num_pairs);
  tbb::parallel_for(0, num_frames, [&](int f) {
    std::vector<ImageF> range(num_cams);
    for (int c = 0; c < num_cams; ++c) {
      if (!have_depth[image_index(c, f)]) continue;
      const auto path = layout.Depth(rig.cameras[c].name, frames_file.frames[f].name);
      range[c] = ReadImageF(path);
      if (!range[c].SameSize(rig.cameras[c].camera.width(), rig.cameras[c].camera.height()) || range[c].channels != 1) {
        throw std::runtime_error(path.string() + ": range image must be 1 channel of the camera's size");
      }
    }
    for (int m = 0; m < num_modes; ++m) {
      for (int p = 0; p < num_pairs; ++p) {
        const int a = pairs[p].a, b = pairs[p].b;
        if (range[a].empty() || range[b].empty()) continue;
        const int mp = m * num_pairs + p;
        const PooledMatches& pm = pooled[mp];
        const int begin = pm.frame_begin[f], end = pm.frame_begin[f + 1];
        const std::vector<Eigen::Vector2d> pa(pm.px_a.begin() + begin, pm.px_a.begin() + end);
        const std::vector<Eigen::Vector2d> pb(pm.px_b.begin() + begin, pm.px_b.begin() + end);
        Counts& cnt = counts[f * num_modes * num_pairs + mp];
        int at_infinity = 0;
        const std::vector<char> ok = CheckMatches(pa, pb, rig.cameras[a].camera, range[a], rig.cameras[b].camera,
                                                  range[b], *reports[m].pairs[p].cam_b_from_cam_a_gt,
                                                  options.precision, &at_infinity);
        cnt.evaluated = true;
        cnt.all.evaluated = end - begin;
        cnt.all.at_infinity = at_infinity;
        const TwoViewResult& tv = two_view[mp];
        for (int i = 0; i < end - begin; ++i) {
          cnt.all.correct += ok[i];
          if (tv.success && tv.inlier_mask[begin + i]) {
            ++cnt.inliers.evaluated;
            cnt.inliers.correct += ok[i];
          }
        }
      }
    }
  });
  for (int m = 0; m < num_modes; ++m) {
    for (int p = 0; p < num_pairs; ++p) {
      MatchPrecisionCounts all, inl;
      bool any = false;
      for (int f = 0; f < num_frames; ++f) {
        const Counts& cnt = counts[f * num_modes * num_pairs + m * num_pairs + p];
        any = any || cnt.evaluated;
        all += cnt.all;
        inl += cnt.inliers;
      }
      if (!any) continue;
      PairResult& pr = reports[m].pairs[p];
      pr.matches_evaluated = all.evaluated;
      pr.matches_correct = all.correct;
      pr.matches_at_infinity = all.at_infinity;
      if (all.evaluated > 0) pr.match_precision = all.Precision();
      pr.inliers_evaluated = inl.evaluated;
      pr.inliers_correct = inl.correct;
      if (inl.evaluated > 0) pr.inlier_precision = inl.Precision();
    }
  }
  return reports;
}

namespace {

nlohmann::json OptionalToJson(const std::optional<double>& v) {
  return v && std::isfinite(*v) ? nlohmann::json(*v) : nlohmann::json(nullptr);
}

nlohmann::json PairToJson(const PairResult& pr) {
  nlohmann::json j;
  j["cam_a"] = pr.cam_a;
  j["cam_b"] = pr.cam_b;
  j["success"] = pr.success;
  j["rotation_only"] = pr.rotation_only;
  j["pair_type"] = pr.success ? nlohmann::json(std::string(PairTypeName(pr.pair_type))) : nlohmann::json(nullptr);
  j["failure_reason"] = pr.failure_reason;
  j["frames"] = pr.frames;
  j["matches"] = pr.matches;
  j["inliers"] = pr.inliers;
  j["homography_inliers"] = pr.homography_inliers;
  j["inlier_ratio"] = pr.matches > 0 ? nlohmann::json(double(pr.inliers) / pr.matches) : nlohmann::json(nullptr);
  j["median_residual_deg"] = pr.success ? nlohmann::json(pr.median_residual_deg) : nlohmann::json(nullptr);
  j["rotation_error_deg"] = OptionalToJson(pr.rotation_error_deg);
  j["translation_direction_error_deg"] = OptionalToJson(pr.translation_direction_error_deg);
  j["match_precision"] = OptionalToJson(pr.match_precision);
  j["matches_evaluated"] = pr.matches_evaluated;
  j["matches_correct"] = pr.matches_correct;
  j["matches_at_infinity"] = pr.matches_at_infinity;
  j["inlier_precision"] = OptionalToJson(pr.inlier_precision);
  j["inliers_evaluated"] = pr.inliers_evaluated;
  j["inliers_correct"] = pr.inliers_correct;
  j["distance_evaluations"] = pr.distance_evaluations;
  j["match_time_s"] = pr.match_time_s;
  j["pose_time_s"] = pr.pose_time_s;
  if (pr.success) {
    const Rigid3d& e = pr.cam_b_from_cam_a;
    j["cam_b_from_cam_a"] = {{"rotation_wxyz", {e.rotation.w(), e.rotation.x(), e.rotation.y(), e.rotation.z()}},
                             {"translation", {e.translation.x(), e.translation.y(), e.translation.z()}}};
  } else {
    j["cam_b_from_cam_a"] = nullptr;
  }
  return j;
}

// Pose error of a pair for the AUC: max of rotation and translation-direction errors; failures
// and unknown translations (rotation-only estimate of a rig with a baseline) are infinite.
double PoseError(const PairResult& pr) {
  const double inf = std::numeric_limits<double>::infinity();
  if (!pr.success || !pr.rotation_error_deg) return inf;
  const bool gt_has_baseline = pr.cam_b_from_cam_a_gt && pr.cam_b_from_cam_a_gt->translation.norm() > 1e-9;
  if (!gt_has_baseline) return *pr.rotation_error_deg;
  if (!pr.translation_direction_error_deg) return inf;
  return std::max(*pr.rotation_error_deg, *pr.translation_direction_error_deg);
}

}  // namespace

nlohmann::json ReportToJson(const std::vector<CalibrationReport>& reports) {
  nlohmann::json methods = nlohmann::json::object();
  for (const CalibrationReport& rep : reports) {
    nlohmann::json m;
    nlohmann::json pairs = nlohmann::json::array();
    std::vector<double> pose_errors, rotation_errors;
    int succeeded = 0, rotation_only = 0, planar = 0;
    int64_t matches = 0, inliers = 0, evaluated = 0, correct = 0;
    bool has_truth = false;
    for (const PairResult& pr : rep.pairs) {
      pairs.push_back(PairToJson(pr));
      succeeded += pr.success;
      rotation_only += pr.rotation_only;
      planar += pr.success && pr.pair_type == PairType::kPlanar;
      matches += pr.matches;
      inliers += pr.inliers;
      evaluated += pr.matches_evaluated;
      correct += pr.matches_correct;
      if (pr.cam_b_from_cam_a_gt) {
        has_truth = true;
        pose_errors.push_back(PoseError(pr));
        rotation_errors.push_back(pr.rotation_error_deg.value_or(std::numeric_limits<double>::infinity()));
      }
    }
    nlohmann::json summary;
    summary["pairs"] = rep.pairs.size();
    summary["pairs_succeeded"] = succeeded;
    summary["pairs_rotation_only"] = rotation_only;
    summary["pairs_planar"] = planar;
    summary["matches"] = matches;
    summary["inliers"] = inliers;
    summary["mean_keypoints_per_image"] = rep.mean_keypoints_per_image;
    summary["match_precision"] = evaluated > 0 ? nlohmann::json(double(correct) / evaluated) : nlohmann::json(nullptr);
    if (has_truth) {
      for (double t : {1.0, 2.0, 5.0, 10.0}) {
        const std::string key = std::to_string(static_cast<int>(t));
        summary["pose_auc"][key] = PoseAuc(pose_errors, t);
        summary["rotation_auc"][key] = PoseAuc(rotation_errors, t);
      }
    }
    m["summary"] = summary;
    m["timing"] = {{"detect_time_s", rep.detect_time_s},
                   {"screen_time_s", rep.screen_time_s},
                   {"match_time_s", rep.match_time_s},
                   {"pose_time_s", rep.pose_time_s},
                   {"temporal_match_time_s", rep.temporal_match_time_s},
                   {"temporal_pose_time_s", rep.temporal_pose_time_s}};
    m["num_cameras"] = rep.num_cameras;
    m["num_frames"] = rep.num_frames;
    m["pairs"] = pairs;
    methods[rep.semantic_mode] = m;
  }
  return {{"methods", methods}};
}

}  // namespace rigsim
