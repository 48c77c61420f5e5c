#include "calibrator/pairwise.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <stdexcept>

#include <opencv2/core.hpp>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>

#include "calibrator/intrinsics_refinement.h"
#include "calibrator/keep_freed_memory.h"
#include "dataset/dataset.h"
#include "dataset/image_io.h"
#include "dataset/label_image.h"
#include "evaluation/pose_errors.h"
#include "evaluation/verdicts.h"
#include "geometry/json_io.h"
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

// What every stage works on: the dataset's cameras, frames and photos, the modes and the camera
// pairs, and how the stages index their work items.
struct PairwiseJob {
  DatasetLayout layout;
  Rig rig;  // with the intrinsics to calibrate with (CalibrationOptions::intrinsics, else rig.json's)
  // rig.json as read: its intrinsics are the truth the matches are checked with.
  Rig truth;
  FramesFile frames;
  std::vector<SemanticMode> modes;
  std::vector<PairIndex> pairs;            // every camera pair, a < b in rig order
  std::vector<std::filesystem::path> image_paths;  // per image (Image order)
  int num_cams = 0, num_frames = 0, num_modes = 0, num_pairs = 0;

  int NumImages() const { return num_cams * num_frames; }
  int Image(int cam, int frame) const { return cam * num_frames + frame; }
  // (mode, pair) and (mode, pair, frame) work items.
  int ModePair(int m, int p) const { return m * num_pairs + p; }
  int ModePairFrame(int m, int p, int f) const { return (m * num_pairs + p) * num_frames + f; }
  MatchOptions Matching(const CalibrationOptions& options, int m) const {
    MatchOptions mo = options.matching;
    mo.gate_by_class = UsesGating(modes[m]);
    return mo;
  }
};

// Features of every image, per kind (kUnmasked, kMasked); a kind no mode uses stays empty.
struct DetectedFeatures {
  std::vector<FeatureSet> of_kind[2];
  std::vector<double> time_s[2];  // per image

  const std::vector<FeatureSet>& Of(SemanticMode m) const { return of_kind[FeatureKind(m)]; }
};

// Pair screening (CalibrationOptions::screen_features), per (mode, pair).
struct PairScreening {
  std::vector<std::string> screened_out;  // the reason; empty = match in full
  std::vector<double> time_s;
};

// Matches per (mode, pair, frame).
struct FrameMatches {
  std::vector<std::vector<Match>> matches;
  std::vector<MatchStats> stats;
};

// Matches of one (mode, pair), pooled over frames in frame order.
struct PooledMatches {
  std::vector<Eigen::Vector2d> px_a, px_b;
  std::vector<int> frame_begin;  // offset of each frame's matches; frame_begin[num_frames] = size
};

// The two-view estimate of each (mode, pair) over its pooled matches.
struct PairFits {
  std::vector<PooledMatches> pooled;
  std::vector<TwoViewResult> two_view;
  std::vector<double> pose_time_s;
};

// Each camera with itself between consecutive frames, per (mode, camera, frame step), camera-major
// within a mode.
struct TemporalFits {
  std::vector<TemporalPairEstimate> estimates;
  std::vector<double> match_time_s, pose_time_s;
};

// 0. Reads rig.json and the frames, and checks that every photo is there and has its camera's
//    size, from the file headers before any is decoded: a missing or wrong photo stops the run at
//    once, not after minutes of detection.
PairwiseJob CheckInputs(const std::filesystem::path& dataset_dir, const std::vector<SemanticMode>& modes,
                        const CalibrationOptions& options) {
  if (modes.empty()) throw std::invalid_argument("CalibrateDatasetPairs: no semantic mode given");
  PairwiseJob job{DatasetLayout(dataset_dir), {}, {}, {}, modes, {}, {}};
  job.truth = ReadRig(job.layout.RigJson());
  job.rig = CalibrationRig(job.truth, options);
  job.num_cams = static_cast<int>(job.rig.cameras.size());
  if (job.num_cams < 2) throw std::runtime_error(job.layout.RigJson().string() + ": calibration needs at least 2 cameras");
  job.frames = job.layout.ReadFramesOrScan(job.rig.cameras[0].name);
  job.num_frames = static_cast<int>(job.frames.frames.size());
  if (job.num_frames == 0) throw std::runtime_error(dataset_dir.string() + ": no frames found");
  for (int a = 0; a < job.num_cams; ++a) {
    for (int b = a + 1; b < job.num_cams; ++b) job.pairs.push_back({a, b});
  }
  job.num_modes = static_cast<int>(modes.size());
  job.num_pairs = static_cast<int>(job.pairs.size());

  job.image_paths.resize(job.NumImages());
  for (int cam = 0; cam < job.num_cams; ++cam) {
    const RigCamera& rc = job.rig.cameras[cam];
    for (int frame = 0; frame < job.num_frames; ++frame) {
      const std::filesystem::path path = job.layout.RequireImage(rc.name, job.frames.frames[frame].name);
      const ImageSize size = ReadImageSize(path);
      const int w = rc.camera.width(), h = rc.camera.height();
      if (size.width != w || size.height != h) {
        throw std::runtime_error(path.string() + ": image is " + std::to_string(size.width) + "x" +
                                 std::to_string(size.height) + ", camera '" + rc.name + "' is " + std::to_string(w) +
                                 "x" + std::to_string(h));
      }
      job.image_paths[job.Image(cam, frame)] = path;
    }
  }
  return job;
}

// 1. Features: one task per image; each image (and its labels) is read once for all kinds.
DetectedFeatures DetectAllFeatures(const PairwiseJob& job, const CalibrationOptions& options) {
  bool need_kind[2] = {false, false};
  bool need_labels = false;
  for (SemanticMode m : job.modes) {
    need_kind[FeatureKind(m)] = true;
    need_labels = need_labels || NeedsLabels(m);
  }
  DetectedFeatures out;
  for (int k = 0; k < 2; ++k) {
    if (need_kind[k]) {
      out.of_kind[k].resize(job.NumImages());
      out.time_s[k].assign(job.NumImages(), 0.0);
    }
  }
  const KeepFreedMemory keep_freed_memory;  // each image's scale space reuses the last one's memory
  tbb::parallel_for(0, job.NumImages(), [&](int idx) {
    const int cam = idx / job.num_frames, frame = idx % job.num_frames;
    const RigCamera& rc = job.rig.cameras[cam];
    const std::string& frame_name = job.frames.frames[frame].name;
    const ImageU8 rgb = ReadImageU8(job.image_paths[idx], 3);
    const int w = rc.camera.width(), h = rc.camera.height();
    ImageU8 labels;
    // Checks size and Cityscapes ids or colours; names the file.
    if (need_labels) labels = LoadLabels(options.labels, job.layout, rc.name, frame_name, w, h);
    for (int k = 0; k < 2; ++k) {
      if (!need_kind[k]) continue;
      const auto start = Clock::now();
      out.of_kind[k][idx] = DetectFeatures(rgb, need_labels ? &labels : nullptr, options.features,
                                           k == kMasked ? &options.reliable : nullptr);
      out.time_s[k][idx] = Seconds(start);
    }
  });
  return out;
}

// 2a. Screening: which (mode, pair)s are worth matching in full, from the strongest
//     `screen_features` keypoints of the first and the middle frame.
PairScreening ScreenPairs(const PairwiseJob& job, const DetectedFeatures& features, const CalibrationOptions& options) {
  PairScreening out;
  out.screened_out.resize(job.num_modes * job.num_pairs);
  out.time_s.assign(job.num_modes * job.num_pairs, 0.0);
  if (options.screen_features <= 0) return out;
  std::vector<int> screen_frames = {0};
  if (job.num_frames / 2 > 0) screen_frames.push_back(job.num_frames / 2);
  tbb::parallel_for(0, job.num_modes * job.num_pairs, [&](int mp) {
    const int m = mp / job.num_pairs, p = mp % job.num_pairs;
    const PairIndex& pair = job.pairs[p];
    const auto start = Clock::now();
    const MatchOptions mo = job.Matching(options, m);
    const auto& feats = features.Of(job.modes[m]);
    std::vector<Eigen::Vector2d> px_a, px_b;
    for (int f : screen_frames) {
      const FeatureSet fa = feats[job.Image(pair.a, f)].Head(options.screen_features);
      const FeatureSet fb = feats[job.Image(pair.b, f)].Head(options.screen_features);
      for (const Match& mt : MatchFeatures(fa, fb, mo)) {
        px_a.push_back(fa.keypoints[mt.a].px);
        px_b.push_back(fb.keypoints[mt.b].px);
      }
    }
    // Screening asks whether the views share geometry, not which way the baseline points: a few
    // thousand keypoints may not decide that where the full matches do.
    TwoViewOptions screen_two_view = options.two_view;
    screen_two_view.min_cheirality_points = 1;
    screen_two_view.cheirality_margin = 1.0;
    const TwoViewResult tv = EstimateRelativePose(job.rig.cameras[pair.a].camera, px_a, job.rig.cameras[pair.b].camera,
                                                  px_b, screen_two_view);
    if (!tv.success) {
      out.screened_out[mp] = "screened out (no shared view found among the " + std::to_string(options.screen_features) +
                             " strongest keypoints of " + std::to_string(screen_frames.size()) + " frame(s): " +
                             tv.failure_reason + ")";
    }
    out.time_s[mp] = Seconds(start);
  });
  return out;
}

// 2b. Full matching of the pairs that passed the screening, frame by frame.
FrameMatches MatchPairs(const PairwiseJob& job, const DetectedFeatures& features, const PairScreening& screening,
                        const CalibrationOptions& options) {
  const int num_jobs = job.num_modes * job.num_pairs * job.num_frames;
  FrameMatches out;
  out.matches.resize(num_jobs);
  out.stats.resize(num_jobs);
  tbb::parallel_for(0, num_jobs, [&](int i) {
    const int f = i % job.num_frames;
    const int p = (i / job.num_frames) % job.num_pairs;
    const int m = i / (job.num_frames * job.num_pairs);
    if (!screening.screened_out[job.ModePair(m, p)].empty()) return;
    const auto& feats = features.Of(job.modes[m]);
    out.matches[i] = MatchFeatures(feats[job.Image(job.pairs[p].a, f)], feats[job.Image(job.pairs[p].b, f)],
                                   job.Matching(options, m), &out.stats[i]);
  });
  return out;
}

// 3. Pools the frames of each (mode, pair); one two-view estimate each.
PairFits PoolAndEstimatePairs(const PairwiseJob& job, const DetectedFeatures& features, const FrameMatches& matches,
                              const PairScreening& screening, const CalibrationOptions& options) {
  PairFits out;
  out.pooled.resize(job.num_modes * job.num_pairs);
  out.two_view.resize(job.num_modes * job.num_pairs);
  out.pose_time_s.assign(job.num_modes * job.num_pairs, 0.0);
  tbb::parallel_for(0, job.num_modes * job.num_pairs, [&](int mp) {
    const int m = mp / job.num_pairs, p = mp % job.num_pairs;
    const PairIndex& pair = job.pairs[p];
    const auto& feats = features.Of(job.modes[m]);
    PooledMatches& pm = out.pooled[mp];
    for (int f = 0; f < job.num_frames; ++f) {
      pm.frame_begin.push_back(static_cast<int>(pm.px_a.size()));
      const FeatureSet& fa = feats[job.Image(pair.a, f)];
      const FeatureSet& fb = feats[job.Image(pair.b, f)];
      for (const Match& mt : matches.matches[job.ModePairFrame(m, p, f)]) {
        pm.px_a.push_back(fa.keypoints[mt.a].px);
        pm.px_b.push_back(fb.keypoints[mt.b].px);
      }
    }
    pm.frame_begin.push_back(static_cast<int>(pm.px_a.size()));
    if (!screening.screened_out[mp].empty()) {
      out.two_view[mp].failure_reason = screening.screened_out[mp];
      return;
    }
    const auto start = Clock::now();
    out.two_view[mp] = EstimateRelativePose(job.rig.cameras[pair.a].camera, pm.px_a, job.rig.cameras[pair.b].camera,
                                            pm.px_b, options.two_view);
    out.pose_time_s[mp] = Seconds(start);
  });
  return out;
}

// 4. One report per mode: every pair's outcome and cost, the stage times.
std::vector<CalibrationReport> BuildReports(const PairwiseJob& job, const DetectedFeatures& features,
                                            const FrameMatches& matches, const PairScreening& screening,
                                            const PairFits& fits) {
  std::vector<CalibrationReport> reports(job.num_modes);
  for (int m = 0; m < job.num_modes; ++m) {
    CalibrationReport& rep = reports[m];
    rep.semantic_mode = std::string(SemanticModeName(job.modes[m]));
    rep.num_cameras = job.num_cams;
    rep.num_frames = job.num_frames;
    const int kind = FeatureKind(job.modes[m]);
    double keypoints = 0.0;
    for (int i = 0; i < job.NumImages(); ++i) {
      keypoints += features.of_kind[kind][i].size();
      rep.detect_time_s += features.time_s[kind][i];
    }
    rep.mean_keypoints_per_image = keypoints / job.NumImages();
    for (int p = 0; p < job.num_pairs; ++p) {
      const int mp = job.ModePair(m, p);
      PairResult pr;
      pr.cam_a = job.rig.cameras[job.pairs[p].a].name;
      pr.cam_b = job.rig.cameras[job.pairs[p].b].name;
      pr.frames = job.num_frames;
      pr.two_view = ToEstimate(fits.two_view[mp], static_cast<int>(fits.pooled[mp].px_a.size()));
      for (int f = 0; f < job.num_frames; ++f) {
        const MatchStats& s = matches.stats[job.ModePairFrame(m, p, f)];
        pr.distance_evaluations += s.distance_evaluations;
        pr.match_time_s += s.time_s;
      }
      pr.pose_time_s = fits.pose_time_s[mp];
      pr.screen_time_s = screening.time_s[mp];
      rep.screen_time_s += pr.screen_time_s;
      rep.match_time_s += pr.match_time_s;
      rep.pose_time_s += pr.pose_time_s;
      rep.pairs.push_back(std::move(pr));
    }
  }
  return reports;
}

// CalibrationOptions::keep_match_details: every match of mode m's inlier flag (md->matches is
// filled), and the keypoints' classes (the ground-truth flags come with the match precision, AddMatchPrecision).
void KeepMatchDetails(const PairwiseJob& job, const std::vector<FeatureSet>& feats, const PairFits& fits, int m,
                      PairwiseMatchData* md) {
  md->keypoint_classes.assign(job.num_frames, std::vector<std::vector<uint8_t>>(job.num_cams));
  for (int f = 0; f < job.num_frames; ++f) {
    for (int c = 0; c < job.num_cams; ++c) {
      for (const Keypoint& kp : feats[job.Image(c, f)].keypoints) md->keypoint_classes[f][c].push_back(kp.class_id);
    }
  }
  md->match_inlier.assign(job.num_pairs, std::vector<std::vector<char>>(job.num_frames));
  md->match_correct.assign(job.num_pairs, std::vector<std::vector<char>>(job.num_frames));
  for (int p = 0; p < job.num_pairs; ++p) {
    const int mp = job.ModePair(m, p);
    const TwoViewResult& tv = fits.two_view[mp];
    for (int f = 0; f < job.num_frames; ++f) {
      const int begin = fits.pooled[mp].frame_begin[f];
      for (size_t i = 0; i < md->matches[p][f].size(); ++i) {
        md->match_inlier[p][f].push_back(tv.success && tv.inlier_mask[begin + i] ? 1 : 0);
      }
    }
  }
}

// 4. What the rig stage needs of each mode: keypoints and per pair and frame the two-view inliers.
std::vector<PairwiseMatchData> CollectMatchData(const PairwiseJob& job, const DetectedFeatures& features,
                                                const FrameMatches& matches, const PairFits& fits,
                                                const CalibrationOptions& options) {
  std::vector<PairwiseMatchData> out(job.num_modes);
  for (int m = 0; m < job.num_modes; ++m) {
    PairwiseMatchData& md = out[m];
    const auto& feats = features.Of(job.modes[m]);
    md.keypoints.assign(job.num_frames, std::vector<std::vector<Eigen::Vector2d>>(job.num_cams));
    for (int f = 0; f < job.num_frames; ++f) {
      for (int c = 0; c < job.num_cams; ++c) {
        for (const Keypoint& kp : feats[job.Image(c, f)].keypoints) md.keypoints[f][c].push_back(kp.px);
      }
    }
    md.matches.assign(job.num_pairs, std::vector<std::vector<std::pair<int, int>>>(job.num_frames));
    md.inliers.assign(job.num_pairs, std::vector<std::vector<std::pair<int, int>>>(job.num_frames));
    for (int p = 0; p < job.num_pairs; ++p) {
      const int mp = job.ModePair(m, p);
      const TwoViewResult& tv = fits.two_view[mp];
      for (int f = 0; f < job.num_frames; ++f) {
        const std::vector<Match>& mt = matches.matches[job.ModePairFrame(m, p, f)];
        for (size_t i = 0; i < mt.size(); ++i) {
          md.matches[p][f].push_back({mt[i].a, mt[i].b});
          if (tv.success && tv.inlier_mask[fits.pooled[mp].frame_begin[f] + i]) {
            md.inliers[p][f].push_back({mt[i].a, mt[i].b});
          }
        }
      }
    }
    if (options.keep_match_details) KeepMatchDetails(job, feats, fits, m, &md);
  }
  return out;
}

// 4b. Temporal pairs: each camera with itself between consecutive frames, per mode (two or more
//     frames).
TemporalFits EstimateTemporalPairs(const PairwiseJob& job, const DetectedFeatures& features,
                                   const CalibrationOptions& options) {
  const int steps = job.num_frames - 1;
  const int num_temporal = job.num_modes * job.num_cams * steps;
  TemporalFits out;
  out.estimates.resize(num_temporal);
  out.match_time_s.assign(num_temporal, 0.0);
  out.pose_time_s.assign(num_temporal, 0.0);
  tbb::parallel_for(0, num_temporal, [&](int i) {
    const int k = i % steps;
    const int c = (i / steps) % job.num_cams;
    const int m = i / (steps * job.num_cams);
    const auto& feats = features.Of(job.modes[m]);
    const FeatureSet& fa = feats[job.Image(c, k)];
    const FeatureSet& fb = feats[job.Image(c, k + 1)];
    MatchStats stats;
    const std::vector<Match> mt = MatchFeatures(fa, fb, job.Matching(options, m), &stats);
    out.match_time_s[i] = stats.time_s;
    std::vector<Eigen::Vector2d> pa, pb;
    for (const Match& x : mt) {
      pa.push_back(fa.keypoints[x.a].px);
      pb.push_back(fb.keypoints[x.b].px);
    }
    const auto start = Clock::now();
    const TwoViewResult tv =
        EstimateRelativePose(job.rig.cameras[c].camera, pa, job.rig.cameras[c].camera, pb, options.two_view);
    out.pose_time_s[i] = Seconds(start);
    TemporalPairEstimate& te = out.estimates[i];
    te.camera = c;
    te.frame = k;
    te.two_view = ToEstimate(tv, static_cast<int>(mt.size()));
    for (size_t j = 0; j < mt.size(); ++j) {
      te.matches.push_back({mt[j].a, mt[j].b});
      if (tv.success && tv.inlier_mask[j]) te.inliers.push_back({mt[j].a, mt[j].b});
    }
  });
  return out;
}

// 5a. Errors of every solved pair's relative pose against the truth (every cam_from_rig known).
void AddPoseErrors(const PairwiseJob& job, std::vector<CalibrationReport>* reports) {
  for (int m = 0; m < job.num_modes; ++m) {
    for (int p = 0; p < job.num_pairs; ++p) {
      PairResult& pr = (*reports)[m].pairs[p];
      const Rigid3d gt =
          *job.rig.cameras[job.pairs[p].b].cam_from_rig * job.rig.cameras[job.pairs[p].a].cam_from_rig->Inverse();
      pr.cam_b_from_cam_a_gt = gt;
      if (pr.two_view.success) {
        pr.rotation_error_deg = RotationErrorDeg(pr.two_view.cam_b_from_cam_a, gt);
        pr.translation_direction_error_deg = TranslationDirectionErrorDeg(pr.two_view.cam_b_from_cam_a, gt);
      }
    }
  }
}

// 5b. Match precision per pair against the ground-truth range images, where depth/ has them:
//     per frame, each camera's range image is read once for every mode and pair of that frame.
//     Needs the truth's relative poses (AddPoseErrors). With keep_match_details, each match's flag
//     goes to `match_data` too.
void AddMatchPrecision(const PairwiseJob& job, const CalibrationOptions& options, const PairFits& fits,
                       std::vector<CalibrationReport>* reports, std::vector<PairwiseMatchData>* match_data) {
  std::vector<char> have_depth(job.NumImages(), 0);
  for (int c = 0; c < job.num_cams; ++c) {
    for (int f = 0; f < job.num_frames; ++f) {
      have_depth[job.Image(c, f)] =
          std::filesystem::exists(job.layout.Depth(job.rig.cameras[c].name, job.frames.frames[f].name));
    }
  }
  if (std::none_of(have_depth.begin(), have_depth.end(), [](char c) { return c != 0; })) return;

  struct Counts {
    MatchPrecisionCounts all, inliers;
    bool evaluated = false;
    bool labelled = false;  // both label images known
  };
  const int num_mp = job.num_modes * job.num_pairs;
  std::vector<Counts> counts(job.num_frames * num_mp);
  tbb::parallel_for(0, job.num_frames, [&](int f) {
    std::vector<ImageF> range(job.num_cams);
    std::vector<ImageU8> labels(job.num_cams);  // the true labels: what a cross-class match is
    for (int c = 0; c < job.num_cams; ++c) {
      if (!have_depth[job.Image(c, f)]) continue;
      const Camera& camera = job.truth.cameras[c].camera;
      const auto path = job.layout.Depth(job.rig.cameras[c].name, job.frames.frames[f].name);
      range[c] = ReadImageF(path);
      if (!range[c].SameSize(camera.width(), camera.height()) || range[c].channels != 1) {
        throw std::runtime_error(path.string() + ": range image must be 1 channel of the camera's size");
      }
      const auto label_path = job.layout.Label(job.rig.cameras[c].name, job.frames.frames[f].name);
      if (std::filesystem::exists(label_path)) labels[c] = ReadLabelImage(label_path, camera.width(), camera.height());
    }
    for (int m = 0; m < job.num_modes; ++m) {
      for (int p = 0; p < job.num_pairs; ++p) {
        const int a = job.pairs[p].a, b = job.pairs[p].b;
        if (range[a].empty() || range[b].empty()) continue;
        const int mp = job.ModePair(m, p);
        const PooledMatches& pm = fits.pooled[mp];
        const int begin = pm.frame_begin[f], end = pm.frame_begin[f + 1];
        const std::vector<Eigen::Vector2d> pa(pm.px_a.begin() + begin, pm.px_a.begin() + end);
        const std::vector<Eigen::Vector2d> pb(pm.px_b.begin() + begin, pm.px_b.begin() + end);
        Counts& cnt = counts[f * num_mp + mp];
        int at_infinity = 0;
        const std::vector<char> ok =
            CheckMatches(pa, pb, job.truth.cameras[a].camera, range[a], job.truth.cameras[b].camera, range[b],
                         *(*reports)[m].pairs[p].cam_b_from_cam_a_gt, options.precision, &at_infinity);
        if (match_data && options.keep_match_details) (*match_data)[m].match_correct[p][f] = ok;
        cnt.evaluated = true;
        cnt.all.evaluated = end - begin;
        cnt.all.at_infinity = at_infinity;
        cnt.labelled = !labels[a].empty() && !labels[b].empty();
        const std::vector<char> cross =
            cnt.labelled ? CrossClassMatches(pa, pb, labels[a], labels[b]) : std::vector<char>(end - begin, 0);
        const TwoViewResult& tv = fits.two_view[mp];
        for (int i = 0; i < end - begin; ++i) {
          cnt.all.correct += ok[i];
          cnt.all.cross_class += cross[i];
          cnt.all.cross_class_correct += cross[i] && ok[i];
          if (tv.success && tv.inlier_mask[begin + i]) {
            ++cnt.inliers.evaluated;
            cnt.inliers.correct += ok[i];
          }
        }
      }
    }
  });
  for (int m = 0; m < job.num_modes; ++m) {
    for (int p = 0; p < job.num_pairs; ++p) {
      MatchPrecisionCounts all, inl;
      bool any = false, labelled = true;
      for (int f = 0; f < job.num_frames; ++f) {
        const Counts& cnt = counts[f * num_mp + job.ModePair(m, p)];
        any = any || cnt.evaluated;
        labelled = labelled && (!cnt.evaluated || cnt.labelled);
        all += cnt.all;
        inl += cnt.inliers;
      }
      if (!any) continue;
      PairResult& pr = (*reports)[m].pairs[p];
      pr.matches_evaluated = all.evaluated;
      pr.matches_correct = all.correct;
      pr.matches_at_infinity = all.at_infinity;
      if (labelled) {
        pr.cross_class_matches = all.cross_class;
        pr.cross_class_correct = all.cross_class_correct;
      }
      if (all.evaluated > 0) pr.match_precision = all.Precision();
      pr.inliers_evaluated = inl.evaluated;
      pr.inliers_correct = inl.correct;
      if (inl.evaluated > 0) pr.inlier_precision = inl.Precision();
    }
  }
}

}  // namespace

Rig CalibrationRig(const Rig& rig_json, const CalibrationOptions& options) {
  return options.intrinsics ? WithGivenIntrinsics(rig_json, options.intrinsics->rig, options.intrinsics->source) : rig_json;
}

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
  const PairwiseJob job = CheckInputs(dataset_dir, modes, options);
  std::unique_ptr<tbb::global_control> thread_limit;
  if (options.num_threads > 0) {
    thread_limit = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism,
                                                         static_cast<size_t>(options.num_threads));
  }
  const OpenCvSingleThread opencv_single_thread;

  const DetectedFeatures features = DetectAllFeatures(job, options);
  const PairScreening screening = ScreenPairs(job, features, options);
  const FrameMatches matches = MatchPairs(job, features, screening, options);
  const PairFits fits = PoolAndEstimatePairs(job, features, matches, screening, options);
  std::vector<CalibrationReport> reports = BuildReports(job, features, matches, screening, fits);
  if (match_data) {
    *match_data = CollectMatchData(job, features, matches, fits, options);
    if (options.temporal_matches && job.num_frames >= 2) {
      TemporalFits temporal = EstimateTemporalPairs(job, features, options);
      const int per_mode = job.num_cams * (job.num_frames - 1);
      for (int m = 0; m < job.num_modes; ++m) {
        for (int i = 0; i < per_mode; ++i) {
          const int t = m * per_mode + i;
          reports[m].temporal_match_time_s += temporal.match_time_s[t];
          reports[m].temporal_pose_time_s += temporal.pose_time_s[t];
          (*match_data)[m].temporal.push_back(std::move(temporal.estimates[t]));
        }
      }
    }
  }
  if (!options.evaluate || !job.rig.HasAllPoses()) return reports;
  AddPoseErrors(job, &reports);
  AddMatchPrecision(job, options, fits, &reports, match_data);
  return reports;
}

std::string PairStatus(const PairResult& pr) {
  if (!pr.two_view.success) return pr.two_view.failure_reason;
  if (!pr.left_out_by_rig.empty()) return "left out by the rig: " + pr.left_out_by_rig;
  return "ok";
}

std::optional<bool> PairWithinTolerance(const PairResult& pr) {
  if (!pr.cam_b_from_cam_a_gt) return std::nullopt;
  if (!pr.two_view.success) return false;
  return WithinTolerance(pr.rotation_error_deg, pr.two_view.rotation_only ? std::nullopt : pr.translation_direction_error_deg,
                         kPairTolerance);
}

nlohmann::json PairResultToJson(const PairResult& pr) {
  const TwoViewEstimate& tv = pr.two_view;
  nlohmann::json j;
  j["cam_a"] = pr.cam_a;
  j["cam_b"] = pr.cam_b;
  j["success"] = pr.Solved();
  j["rotation_only"] = tv.rotation_only;
  j["pair_type"] = tv.success ? nlohmann::json(std::string(PairTypeName(tv.pair_type))) : nlohmann::json(nullptr);
  j["failure_reason"] = pr.Solved() ? std::string() : PairStatus(pr);
  j["frames"] = pr.frames;
  j["matches"] = tv.num_matches;
  j["inliers"] = tv.num_inliers;
  j["homography_inliers"] = tv.num_homography_inliers;
  j["inlier_ratio"] = tv.num_matches > 0 ? nlohmann::json(double(tv.num_inliers) / tv.num_matches) : nlohmann::json(nullptr);
  j["median_residual_deg"] = tv.success ? nlohmann::json(tv.median_residual_deg) : nlohmann::json(nullptr);
  // Which way the baseline points: of the inliers with parallax enough to tell, how many lie in
  // front of both cameras under the pose and under the best of the other three.
  j["cheirality"] = {{"points", tv.cheirality_points},
                     {"in_front", tv.points_in_front},
                     {"in_front_otherwise", tv.points_in_front_otherwise}};
  j["rotation_error_deg"] = json_io::OptionalNumber(pr.rotation_error_deg);
  j["translation_direction_error_deg"] = json_io::OptionalNumber(pr.translation_direction_error_deg);
  const std::optional<bool> within = PairWithinTolerance(pr);
  j["within_tolerance"] = within ? nlohmann::json(*within) : nlohmann::json(nullptr);
  j["match_precision"] = json_io::OptionalNumber(pr.match_precision);
  j["matches_evaluated"] = pr.matches_evaluated;
  j["matches_correct"] = pr.matches_correct;
  j["matches_at_infinity"] = pr.matches_at_infinity;
  j["cross_class_matches"] = pr.cross_class_matches ? nlohmann::json(*pr.cross_class_matches) : nlohmann::json(nullptr);
  j["cross_class_wrong"] =
      pr.cross_class_matches ? nlohmann::json(*pr.cross_class_matches - pr.cross_class_correct) : nlohmann::json(nullptr);
  j["inlier_precision"] = json_io::OptionalNumber(pr.inlier_precision);
  j["inliers_evaluated"] = pr.inliers_evaluated;
  j["inliers_correct"] = pr.inliers_correct;
  j["distance_evaluations"] = pr.distance_evaluations;
  j["match_time_s"] = pr.match_time_s;
  j["pose_time_s"] = pr.pose_time_s;
  j["cam_b_from_cam_a"] = tv.success ? json_io::PoseToJson(tv.cam_b_from_cam_a) : nlohmann::json(nullptr);
  return j;
}

namespace {

// Pose error of a pair for the AUC (verdicts.h): a pair the calibrator does not stand by, or a
// rotation-only estimate of a rig with a baseline, counts as infinite.
double PoseError(const PairResult& pr) {
  const bool gt_has_baseline = pr.cam_b_from_cam_a_gt && pr.cam_b_from_cam_a_gt->translation.norm() > 1e-9;
  return PoseErrorDeg(pr.Solved(), pr.rotation_error_deg, pr.translation_direction_error_deg, gt_has_baseline);
}

}  // namespace

nlohmann::json ReportToJson(const std::vector<CalibrationReport>& reports) {
  nlohmann::json methods = nlohmann::json::object();
  for (const CalibrationReport& rep : reports) {
    nlohmann::json m;
    nlohmann::json pairs = nlohmann::json::array();
    std::vector<double> pose_errors, rotation_errors;
    int succeeded = 0, rotation_only = 0, planar = 0, within = 0, succeeded_outside = 0;
    int64_t matches = 0, inliers = 0, evaluated = 0, correct = 0, cross = 0, cross_correct = 0;
    bool has_truth = false, has_cross = false;
    for (const PairResult& pr : rep.pairs) {
      pairs.push_back(PairResultToJson(pr));
      if (pr.cross_class_matches) {
        has_cross = true;
        cross += *pr.cross_class_matches;
        cross_correct += pr.cross_class_correct;
      }
      succeeded += pr.Solved();
      rotation_only += pr.two_view.rotation_only;
      planar += pr.two_view.success && pr.two_view.pair_type == PairType::kPlanar;
      matches += pr.two_view.num_matches;
      inliers += pr.two_view.num_inliers;
      evaluated += pr.matches_evaluated;
      correct += pr.matches_correct;
      if (pr.cam_b_from_cam_a_gt) {
        has_truth = true;
        const bool ok = PairWithinTolerance(pr).value_or(false);
        within += ok;
        succeeded_outside += pr.Solved() && !ok;
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
    summary["cross_class_matches"] = has_cross ? nlohmann::json(cross) : nlohmann::json(nullptr);
    summary["cross_class_wrong"] = has_cross ? nlohmann::json(cross - cross_correct) : nlohmann::json(nullptr);
    summary["tolerance"] = {{"rotation_deg", kPairTolerance.rotation_deg}, {"direction_deg", kPairTolerance.direction_deg}};
    summary["pairs_within_tolerance"] = has_truth ? nlohmann::json(within) : nlohmann::json(nullptr);
    summary["pairs_succeeded_outside_tolerance"] = has_truth ? nlohmann::json(succeeded_outside) : nlohmann::json(nullptr);
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
