#include "calibrator/calibrate_rig.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <memory>
#include <mutex>
#include <tuple>
#include <utility>
#include <vector>

#include "calibrator/motion_passes.h"
#include "calibrator/rig_intrinsics.h"
#include "calibrator/stages/stage_clock.h"

namespace rigsim {
namespace {

// The rig stages' observations: the views' cameras and the pairwise stage's outcome.
RigObservations ObservationsOfPairs(const RigViews& views, const PairwiseResult& pairwise) {
  RigObservations obs;
  obs.camera_names = views.camera_names;
  obs.cameras = views.cameras;
  const PairwiseMatchData& data = pairwise.matches;
  obs.keypoints = data.keypoints;
  for (size_t p = 0; p < pairwise.report.pairs.size(); ++p) {
    const PairResult& pr = pairwise.report.pairs[p];
    int a = -1, b = -1;
    for (int c = 0; c < static_cast<int>(views.camera_names.size()); ++c) {
      if (views.camera_names[c] == pr.cam_a) a = c;
      if (views.camera_names[c] == pr.cam_b) b = c;
    }
    const PairEstimate e{a, b, pr.two_view};
    obs.pairs.push_back(e);
    obs.inliers.push_back({e.cam_a, e.cam_b, data.inliers[p]});
    obs.matches.push_back({e.cam_a, e.cam_b, data.matches[p]});
  }
  obs.temporal = data.temporal;
  obs.frame_times_s = views.frame_times_s;
  obs.readout_bottom_to_top = views.readout_bottom_to_top;
  return obs;
}

// `match`, each view pair matched once: the motion stage's passes, the track registration's rounds and
// the intrinsics' two passes ask for the same view pairs again, and their matches depend on the
// views alone. Called from several threads at once.
ViewPairMatcher MatchingEachPairOnce(ViewPairMatcher match) {
  using ViewPair = std::tuple<int, int, int, int>;
  auto matched = std::make_shared<std::map<ViewPair, std::vector<std::pair<int, int>>>>();
  auto guard = std::make_shared<std::mutex>();
  return [match = std::move(match), matched, guard](int cam_a, int frame_a, int cam_b, int frame_b) {
    const ViewPair key{cam_a, frame_a, cam_b, frame_b};
    {
      const std::lock_guard<std::mutex> lock(*guard);
      if (const auto it = matched->find(key); it != matched->end()) return it->second;
    }
    std::vector<std::pair<int, int>> m = match(cam_a, frame_a, cam_b, frame_b);
    const std::lock_guard<std::mutex> lock(*guard);
    return matched->emplace(key, std::move(m)).first->second;
  };
}

}  // namespace

void UseReestimatedPairs(RigCalibrationResult* result) {
  if (result->reestimated_pairs.size() != result->pairwise.pairs.size()) return;
  for (size_t p = 0; p < result->pairwise.pairs.size(); ++p) result->pairwise.pairs[p].two_view = result->reestimated_pairs[p];
}

void MarkPairsTheRigLeftOut(RigCalibrationResult* result) {
  for (const RigEdgeStats& e : result->edges) {
    const bool left_out = e.outcome == EdgeOutcome::kRejected || e.outcome == EdgeOutcome::kRotationOutlier;
    if (!left_out && !e.direction_left_out) continue;
    for (PairResult& pr : result->pairwise.pairs) {
      if (pr.cam_a == e.cam_a && pr.cam_b == e.cam_b) pr.left_out_by_rig = e.status;
    }
  }
}

// Each stated deviation becomes the larger of the covariance's and the jackknives' (over frames
// and over points, jackknife.h): the covariance alone states a pose several times too tightly
// where the keypoints' error is structured, and a deviation rigsim states must bound its error.
// The placement bound (max_direction_std_deg) stays on the covariance, where it was measured.
// The jackknives measure the data's spread alone: the given intrinsics' share of the covariance
// (RigCameraStats::direction_intrinsics_std_deg), independent of it, adds in quadrature.
void StateJackknives(RigCalibrationResult* result) {
  const auto with_intrinsics = [](double jackknife, const std::optional<double>& intrinsics) {
    return intrinsics ? std::hypot(jackknife, *intrinsics) : jackknife;
  };
  for (RigCameraStats& s : result->camera_stats) {
    if (s.rotation_std_deg && s.rotation_jackknife_std_deg) {
      s.rotation_std_deg =
          std::max(*s.rotation_std_deg, with_intrinsics(*s.rotation_jackknife_std_deg, s.rotation_intrinsics_std_deg));
    }
    if (s.direction_std_deg && s.direction_jackknife_std_deg) {
      s.direction_std_deg =
          std::max(*s.direction_std_deg, with_intrinsics(*s.direction_jackknife_std_deg, s.direction_intrinsics_std_deg));
    }
  }
}

RigCalibrationResult EstimateRigFromPairs(const RigViews& views, const PairwiseResult& pairwise,
                                          const RigCalibrationOptions& options) {
  const RigObservations obs = ObservationsOfPairs(views, pairwise);
  // Every run of the rig stage, both of the intrinsics' passes included, with the motion stage's
  // links where they apply.
  const bool refine = options.bundle_adjustment.refine_intrinsics;
  const ViewPairMatcher match = MatchingEachPairOnce(MatcherOfViews(views, options.pairwise.matching));
  const RigPass with_motion = [&match](const RigObservations& o, const RigCalibrationOptions& opt) {
    return EstimateRigWithMotionLinks(o, match, opt);
  };
  RigCalibrationResult r = refine ? EstimateRigAndIntrinsics(obs, options, with_motion) : with_motion(obs, options);
  StateJackknives(&r);
  r.pairwise = pairwise.report;
  UseReestimatedPairs(&r);
  MarkPairsTheRigLeftOut(&r);
  if (r.details) r.details->matches = pairwise.matches;
  return r;
}

RigCalibrationResult CalibrateRig(const RigViews& views, const RigCalibrationOptions& options,
                                  PairwiseMatchData* keep_matches) {
  options.Check();
  PairwiseOptions pairwise = options.pairwise;
  pairwise.keep_match_details = pairwise.keep_match_details || options.keep_details;
  options.Tell("matching the camera pairs");
  PairwiseResult matched = MatchRigPairs(views, pairwise);
  RigCalibrationResult r = EstimateRigFromPairs(views, matched, options);
  if (keep_matches != nullptr) *keep_matches = std::move(matched.matches);
  return r;
}

}  // namespace rigsim
