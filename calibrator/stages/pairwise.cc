#include "calibrator/stages/pairwise.h"

#include <chrono>
#include <stdexcept>

#include <tbb/parallel_for.h>

#include "calibrator/features/parallel_scope.h"
#include "calibrator/stages/stage_clock.h"

namespace rigsim {
namespace {

struct PairIndex {
  int a, b;
};

// What every stage works on: the views, the camera pairs, and how the stages index their work
// items.
struct PairwiseJob {
  const RigViews& views;
  std::vector<PairIndex> pairs;  // every camera pair, a < b in rig order
  int num_cams = 0, num_frames = 0, num_pairs = 0;

  const Camera& camera(int c) const { return views.cameras[c]; }
  const FeatureSet& Of(int camera, int frame) const { return views.Of(camera, frame); }
  // (pair, frame) work items.
  int PairFrame(int p, int f) const { return p * num_frames + f; }
};

// Pair screening (PairwiseOptions::screen_features), per pair.
struct PairScreening {
  std::vector<std::string> screened_out;  // the reason; empty = match in full
  std::vector<double> time_s;
};

// Matches per (pair, frame).
struct FrameMatches {
  std::vector<std::vector<Match>> matches;
  std::vector<MatchStats> stats;
};

// Matches of one pair, pooled over frames in frame order.
struct PooledMatches {
  std::vector<Eigen::Vector2d> px_a, px_b;
  std::vector<int> frame_begin;  // offset of each frame's matches; frame_begin[num_frames] = size
};

// The two-view estimate of each pair over its pooled matches.
struct PairFits {
  std::vector<PooledMatches> pooled;
  std::vector<TwoViewResult> two_view;
  std::vector<double> pose_time_s;
};

// Each camera with itself between consecutive frames, per (camera, frame step), camera-major.
struct TemporalFits {
  std::vector<TemporalPairEstimate> estimates;
  std::vector<double> match_time_s, pose_time_s;
};

PairwiseJob MakeJob(const RigViews& views) {
  PairwiseJob job{views, {}};
  job.num_cams = static_cast<int>(views.cameras.size());
  job.num_frames = views.num_frames;
  for (int a = 0; a < job.num_cams; ++a) {
    for (int b = a + 1; b < job.num_cams; ++b) job.pairs.push_back({a, b});
  }
  job.num_pairs = static_cast<int>(job.pairs.size());
  return job;
}

// 1a. Screening: which pairs are worth matching in full, from the strongest `screen_features`
//     keypoints of the first and the middle frame.
PairScreening ScreenPairs(const PairwiseJob& job, const PairwiseOptions& options) {
  PairScreening out;
  out.screened_out.resize(job.num_pairs);
  out.time_s.assign(job.num_pairs, 0.0);
  if (options.screen_features <= 0) return out;
  std::vector<int> screen_frames = {0};
  if (job.num_frames / 2 > 0) screen_frames.push_back(job.num_frames / 2);
  tbb::parallel_for(0, job.num_pairs, [&](int p) {
    const PairIndex& pair = job.pairs[p];
    const auto start = StageClock::now();
    std::vector<Eigen::Vector2d> px_a, px_b;
    for (int f : screen_frames) {
      const FeatureSet fa = job.Of(pair.a, f).Head(options.screen_features);
      const FeatureSet fb = job.Of(pair.b, f).Head(options.screen_features);
      for (const Match& mt : MatchFeatures(fa, fb, options.matching)) {
        px_a.push_back(fa.keypoints[mt.a].px);
        px_b.push_back(fb.keypoints[mt.b].px);
      }
    }
    // Screening asks whether the views share geometry, not which way the baseline points: a few
    // thousand keypoints may not decide that where the full matches do.
    TwoViewOptions screen_two_view = WithoutRivalSearch(options.two_view);  // a rival still shows a shared view
    screen_two_view.min_cheirality_points = 1;
    screen_two_view.cheirality_margin = 1.0;
    const TwoViewResult tv = EstimateRelativePose(job.camera(pair.a), px_a, job.camera(pair.b), px_b, screen_two_view);
    if (!tv.estimate.success) {
      out.screened_out[p] = "screened out (no shared view found among the " + std::to_string(options.screen_features) +
                            " strongest keypoints of " + std::to_string(screen_frames.size()) + " frame(s): " +
                            tv.estimate.failure_reason + ")";
    }
    out.time_s[p] = SecondsSince(start);
  });
  return out;
}

// 1b. Full matching of the pairs that passed the screening, frame by frame.
FrameMatches MatchPairs(const PairwiseJob& job, const PairScreening& screening, const PairwiseOptions& options) {
  const int num_jobs = job.num_pairs * job.num_frames;
  FrameMatches out;
  out.matches.resize(num_jobs);
  out.stats.resize(num_jobs);
  tbb::parallel_for(0, num_jobs, [&](int i) {
    const int f = i % job.num_frames;
    const int p = i / job.num_frames;
    if (!screening.screened_out[p].empty()) return;
    out.matches[i] = MatchFeatures(job.Of(job.pairs[p].a, f), job.Of(job.pairs[p].b, f), options.matching, &out.stats[i]);
  });
  return out;
}

// 2. Pools the frames of each pair; one two-view estimate each.
PairFits PoolAndEstimatePairs(const PairwiseJob& job, const FrameMatches& matches, const PairScreening& screening,
                              const PairwiseOptions& options) {
  PairFits out;
  out.pooled.resize(job.num_pairs);
  out.two_view.resize(job.num_pairs);
  out.pose_time_s.assign(job.num_pairs, 0.0);
  tbb::parallel_for(0, job.num_pairs, [&](int p) {
    const PairIndex& pair = job.pairs[p];
    PooledMatches& pm = out.pooled[p];
    for (int f = 0; f < job.num_frames; ++f) {
      pm.frame_begin.push_back(static_cast<int>(pm.px_a.size()));
      const FeatureSet& fa = job.Of(pair.a, f);
      const FeatureSet& fb = job.Of(pair.b, f);
      for (const Match& mt : matches.matches[job.PairFrame(p, f)]) {
        pm.px_a.push_back(fa.keypoints[mt.a].px);
        pm.px_b.push_back(fb.keypoints[mt.b].px);
      }
    }
    pm.frame_begin.push_back(static_cast<int>(pm.px_a.size()));
    if (!screening.screened_out[p].empty()) {
      out.two_view[p].estimate.failure_reason = screening.screened_out[p];  // not estimated
      return;
    }
    const auto start = StageClock::now();
    out.two_view[p] = EstimateRelativePose(job.camera(pair.a), pm.px_a, job.camera(pair.b), pm.px_b, options.two_view);
    out.pose_time_s[p] = SecondsSince(start);
  });
  return out;
}

// 3. The report: every pair's outcome and cost, the stage times.
CalibrationReport BuildReport(const PairwiseJob& job, const FrameMatches& matches, const PairScreening& screening,
                              const PairFits& fits) {
  CalibrationReport rep;
  rep.num_cameras = job.num_cams;
  rep.num_frames = job.num_frames;
  double keypoints = 0.0;
  for (const FeatureSet& f : job.views.features) keypoints += f.size();
  rep.mean_keypoints_per_image = keypoints / (job.num_cams * job.num_frames);
  for (int p = 0; p < job.num_pairs; ++p) {
    PairResult pr;
    pr.cam_a = job.views.camera_names[job.pairs[p].a];
    pr.cam_b = job.views.camera_names[job.pairs[p].b];
    pr.frames = job.num_frames;
    pr.two_view = fits.two_view[p].estimate;
    pr.screened_out = !screening.screened_out[p].empty();
    for (int f = 0; f < job.num_frames; ++f) {
      const MatchStats& s = matches.stats[job.PairFrame(p, f)];
      pr.distance_evaluations += s.distance_evaluations;
      pr.match_time_s += s.time_s;
    }
    pr.pose_time_s = fits.pose_time_s[p];
    pr.screen_time_s = screening.time_s[p];
    rep.screen_time_s += pr.screen_time_s;
    rep.match_time_s += pr.match_time_s;
    rep.pose_time_s += pr.pose_time_s;
    rep.pairs.push_back(std::move(pr));
  }
  return rep;
}

// PairwiseOptions::keep_match_details: every match's inlier flag (md->matches is filled), and the
// keypoints' classes.
void KeepMatchDetails(const PairwiseJob& job, const PairFits& fits, PairwiseMatchData* md) {
  md->keypoint_classes.assign(job.num_frames, std::vector<std::vector<uint8_t>>(job.num_cams));
  for (int f = 0; f < job.num_frames; ++f) {
    for (int c = 0; c < job.num_cams; ++c) {
      for (const Keypoint& kp : job.Of(c, f).keypoints) md->keypoint_classes[f][c].push_back(kp.class_id);
    }
  }
  md->match_inlier.assign(job.num_pairs, std::vector<std::vector<char>>(job.num_frames));
  for (int p = 0; p < job.num_pairs; ++p) {
    const TwoViewResult& tv = fits.two_view[p];
    for (int f = 0; f < job.num_frames; ++f) {
      const int begin = fits.pooled[p].frame_begin[f];
      for (size_t i = 0; i < md->matches[p][f].size(); ++i) {
        md->match_inlier[p][f].push_back(tv.estimate.success && tv.inlier_mask[begin + i] ? 1 : 0);
      }
    }
  }
}

// 3b. What the rig stage needs: keypoints and per pair and frame the matches and two-view inliers.
PairwiseMatchData CollectMatchData(const PairwiseJob& job, const FrameMatches& matches, const PairFits& fits,
                                   const PairwiseOptions& options) {
  PairwiseMatchData md;
  md.keypoints.assign(job.num_frames, std::vector<std::vector<Eigen::Vector2d>>(job.num_cams));
  for (int f = 0; f < job.num_frames; ++f) {
    for (int c = 0; c < job.num_cams; ++c) {
      for (const Keypoint& kp : job.Of(c, f).keypoints) md.keypoints[f][c].push_back(kp.px);
    }
  }
  md.matches.assign(job.num_pairs, std::vector<std::vector<std::pair<int, int>>>(job.num_frames));
  md.inliers.assign(job.num_pairs, std::vector<std::vector<std::pair<int, int>>>(job.num_frames));
  for (int p = 0; p < job.num_pairs; ++p) {
    const TwoViewResult& tv = fits.two_view[p];
    for (int f = 0; f < job.num_frames; ++f) {
      const std::vector<Match>& mt = matches.matches[job.PairFrame(p, f)];
      for (size_t i = 0; i < mt.size(); ++i) {
        md.matches[p][f].push_back({mt[i].a, mt[i].b});
        const bool inlier = tv.estimate.success && tv.inlier_mask[fits.pooled[p].frame_begin[f] + i];
        if (inlier) md.inliers[p][f].push_back({mt[i].a, mt[i].b});
      }
    }
  }
  if (options.keep_match_details) KeepMatchDetails(job, fits, &md);
  return md;
}

// 4. Temporal pairs: each camera with itself between consecutive frames (two or more frames).
TemporalFits EstimateTemporalPairs(const PairwiseJob& job, const PairwiseOptions& options) {
  const int steps = job.num_frames - 1;
  const int num_temporal = job.num_cams * steps;
  TemporalFits out;
  out.estimates.resize(num_temporal);
  out.match_time_s.assign(num_temporal, 0.0);
  out.pose_time_s.assign(num_temporal, 0.0);
  tbb::parallel_for(0, num_temporal, [&](int i) {
    const int k = i % steps;
    const int c = i / steps;
    const FeatureSet& fa = job.Of(c, k);
    const FeatureSet& fb = job.Of(c, k + 1);
    MatchStats stats;
    const std::vector<Match> mt = MatchFeatures(fa, fb, options.matching, &stats);
    out.match_time_s[i] = stats.time_s;
    std::vector<Eigen::Vector2d> pa, pb;
    for (const Match& x : mt) {
      pa.push_back(fa.keypoints[x.a].px);
      pb.push_back(fb.keypoints[x.b].px);
    }
    const auto start = StageClock::now();
    const TwoViewResult tv =
        EstimateRelativePose(job.camera(c), pa, job.camera(c), pb, WithoutRivalSearch(options.two_view));
    out.pose_time_s[i] = SecondsSince(start);
    TemporalPairEstimate& te = out.estimates[i];
    te.camera = c;
    te.frame = k;
    te.two_view = tv.estimate;
    for (size_t j = 0; j < mt.size(); ++j) {
      te.matches.push_back({mt[j].a, mt[j].b});
      if (tv.estimate.success && tv.inlier_mask[j]) te.inliers.push_back({mt[j].a, mt[j].b});
    }
  });
  return out;
}

}  // namespace

void PairwiseOptions::Check() const {
  matching.Check();
  two_view.Check();
  if (num_threads < 0) throw std::invalid_argument("PairwiseOptions: num_threads must be >= 0");
  if (screen_features < 0) throw std::invalid_argument("PairwiseOptions: screen_features must be >= 0");
}

void RigViews::Check() const {
  const size_t n = cameras.size();
  if (n < 2) throw std::invalid_argument("RigViews: calibration needs at least 2 cameras");
  if (camera_names.size() != n) throw std::invalid_argument("RigViews: one name per camera");
  if (num_frames < 1) throw std::invalid_argument("RigViews: no frames");
  if (features.size() != n * num_frames) throw std::invalid_argument("RigViews: one feature set per camera and frame");
  if (!frame_times_s.empty() && static_cast<int>(frame_times_s.size()) != num_frames) {
    throw std::invalid_argument("RigViews: one timestamp per frame, or none");
  }
  if (!readout_bottom_to_top.empty() && readout_bottom_to_top.size() != n) {
    throw std::invalid_argument("RigViews: one readout order per camera, or none");
  }
}

PairwiseResult MatchRigPairs(const RigViews& views, const PairwiseOptions& options) {
  options.Check();
  views.Check();
  const PairwiseJob job = MakeJob(views);
  const ParallelScope parallel(options.num_threads);
  const PairScreening screening = ScreenPairs(job, options);
  const FrameMatches matches = MatchPairs(job, screening, options);
  const PairFits fits = PoolAndEstimatePairs(job, matches, screening, options);
  PairwiseResult out;
  out.report = BuildReport(job, matches, screening, fits);
  out.matches = CollectMatchData(job, matches, fits, options);
  if (options.temporal_matches && job.num_frames >= 2) {
    TemporalFits temporal = EstimateTemporalPairs(job, options);
    for (size_t i = 0; i < temporal.estimates.size(); ++i) {
      out.report.temporal_match_time_s += temporal.match_time_s[i];
      out.report.temporal_pose_time_s += temporal.pose_time_s[i];
      out.matches.temporal.push_back(std::move(temporal.estimates[i]));
    }
  }
  return out;
}

std::pair<PairEstimate, PairMatches> EstimatePairFromMatches(
    const std::vector<Camera>& cameras, const FrameKeypoints& keypoints, int cam_a, int cam_b,
    const std::vector<std::vector<std::pair<int, int>>>& matches_per_frame, const TwoViewOptions& options) {
  std::vector<Eigen::Vector2d> px_a, px_b;
  for (size_t f = 0; f < matches_per_frame.size(); ++f) {
    for (const auto& [a, b] : matches_per_frame[f]) {
      px_a.push_back(keypoints.at(f).at(cam_a).at(a));
      px_b.push_back(keypoints.at(f).at(cam_b).at(b));
    }
  }
  const TwoViewResult tv = EstimateRelativePose(cameras.at(cam_a), px_a, cameras.at(cam_b), px_b, options);
  const PairEstimate e{cam_a, cam_b, tv.estimate};
  PairMatches inl{cam_a, cam_b, std::vector<std::vector<std::pair<int, int>>>(matches_per_frame.size())};
  if (tv.estimate.success) {
    size_t i = 0;
    for (size_t f = 0; f < matches_per_frame.size(); ++f) {
      for (const auto& m : matches_per_frame[f]) {
        if (tv.inlier_mask[i++]) inl.per_frame[f].push_back(m);
      }
    }
  }
  return {e, inl};
}

PairOutcome PairResult::Outcome() const {
  if (!two_view.success) return screened_out ? PairOutcome::kScreenedOut : PairOutcome::kTwoViewFailed;
  if (left_out_by_rig) return PairOutcome::kLeftOutByRig;
  return PairOutcome::kSolved;
}

std::string PairStatus(const PairResult& pr) {
  switch (pr.Outcome()) {
    case PairOutcome::kSolved: return "ok";
    case PairOutcome::kScreenedOut:
    case PairOutcome::kTwoViewFailed: return pr.two_view.failure_reason;
    case PairOutcome::kLeftOutByRig: return "left out by the rig: " + *pr.left_out_by_rig;
  }
  return "ok";
}

}  // namespace rigsim
