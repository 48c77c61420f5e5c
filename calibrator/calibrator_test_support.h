// What the calibrator's rig tests share beyond the test toolkit (testing/): a synthetic rig's
// observations as the pairwise stage hands them to EstimateRig, a two-camera drive for the bundle
// adjustment's tests, and a result's errors against the truth (the calibrator never sees it; the
// tests do).
#pragma once

#include <random>
#include <vector>

#include "calibrator/estimators/multi_frame_rig.h"
#include "calibrator/estimators/two_view.h"
#include "calibrator/stages/motion_links.h"
#include "calibrator/stages/rig_calibration.h"
#include "evaluation/rig_scores.h"
#include "testing/synthetic_rig.h"

namespace rigsim {

struct SyntheticObservationOptions {
  TwoViewOptions two_view;
  // Also each camera between consecutive frames (RigObservations::temporal): what a moving rig
  // gives the multi-frame stages.
  bool temporal_pairs = false;
};

// Every camera pair's candidate matches per frame (SyntheticRig::CandidateMatches: the true ones
// and outliers) through EstimatePairFromMatches; with temporal_pairs, each camera's consecutive
// frames through EstimateRelativePose too.
RigObservations ObserveSyntheticRig(SyntheticRig& s, const SyntheticObservationOptions& options = {});

// What a matcher finds between two views: the true correspondences and a twentieth as many wrong
// ones, drawn from the view pair alone (the matcher runs on several threads at once). `s` must
// outlive it.
ViewPairMatcher SyntheticMatcher(const SyntheticRig& s);

// A ring of three overlapping cameras that capture at `offsets_s` from their frame's timestamp with
// rolling-shutter `readouts_s` (one per camera), along `path`; every point's track from the truth.
// `timing` starts at zero offsets and readouts, estimating both.
struct TimedRing {
  SyntheticRig s;
  std::vector<ViewTrack> tracks;
  std::vector<Camera> cameras;
  CaptureTiming timing;

  TimedRing(const std::vector<Rigid3d>& path, double noise_px, uint32_t seed, const std::vector<double>& offsets_s,
            const std::vector<double>& readouts_s);
  // The bundle adjustment from the true poses, without filtering, with `with` (nullptr: synchronised).
  MultiFrameBundleAdjustmentResult Adjust(const CaptureTiming* with) const;
};

// Two pinhole cameras 1 m apart, the second turned 20 deg, on a rig that moves 0.5 m and turns
// 3 deg per frame through a field of points 4-12 m away; every point is seen by every view it
// falls in.
struct TwoCameraDrive {
  std::vector<Camera> cameras;
  RigPoses truth;
  std::vector<Eigen::Vector3d> points;
  std::vector<ViewTrack> tracks;
};

TwoCameraDrive MakeTwoCameraDrive(int frames, std::mt19937& rng);

// Every point's projection in every view (keypoint index = point index; unseen ones are never
// referenced), with `noise_px` per coordinate; in `jolted_frame` camera 1 sees from
// `jolt * cam_from_rig` instead of its place in the rig (a mount that gives for a moment).
FrameKeypoints ObserveTwoCameraDrive(const TwoCameraDrive& d, double noise_px, std::mt19937& rng, int jolted_frame = -1,
                                     const Rigid3d& jolt = Rigid3d());

// Per camera, `result`'s errors against `truth` with camera 0 as the rig frame, as evaluation.json
// states them (evaluation/rig_scores.h CalibrationCameraErrors).
std::vector<CameraErrors> ErrorsAgainst(const Rig& truth, const RigCalibrationResult& result);

}  // namespace rigsim
