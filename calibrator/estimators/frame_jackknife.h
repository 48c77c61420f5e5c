// The rig's bundle adjustment run again with each frame left out (a delete-one jackknife over
// frames): how far each camera's pose in the rig moves, as a deviation beside the covariance's.
//
// The covariance (bundle_covariance.h) counts the residuals as independent errors around a model
// that fits. On real photos and renders alike the keypoints' error is structured (it grows with
// octave, near depth edges and under foreshortening, and repeats on one texture), and then the
// poses move several times further than the covariance says. Frames are the units that error does
// not span: each brings its own views of the scene. The jackknife needs no model of the error, only
// three or more posed frames.
#pragma once

#include <optional>
#include <vector>

#include "calibrator/estimators/multi_frame_rig.h"
#include "calibrator/model/correspondences.h"
#include "calibrator/model/rig_state.h"
#include "calibrator/model/tracks.h"
#include "geometry/camera.h"

namespace rigsim {

// What a bundle adjustment was given and what it found (MultiFrameRigBundleAdjust's arguments,
// its solution as the start), in the adjustment's own units.
struct RigAdjustmentProblem {
  std::vector<Camera> cameras;  // as given (with refine_intrinsics: the priors' centres)
  FrameKeypoints keypoints;
  std::vector<ViewTrack> tracks;
  RigPoses solution;
  int scale_camera = -1;
  RigBundleAdjustmentOptions options;
  bool hold_frames = false;
  std::optional<CaptureTiming> timing;  // its offsets and readouts those the adjustment found
};

// The problem MultiFrameRigBundleAdjust was given (its arguments) with `solved`'s poses and timing.
RigAdjustmentProblem SolvedProblem(const std::vector<Camera>& cameras, const FrameKeypoints& keypoints,
                                   const std::vector<ViewTrack>& tracks, int scale_camera,
                                   const RigBundleAdjustmentOptions& options, bool hold_frames,
                                   const CaptureTiming* timing, const MultiFrameBundleAdjustmentResult& solved);

struct FrameJackknife {
  // Adjustments run: one per posed frame, or beyond 10 posed frames one per run of consecutive
  // frames left out together (10 runs); none with fewer than 3 posed frames.
  int groups_left_out = 0;
  // Per camera, from the spread of its pose over those adjustments ((m - 1) / m times the sum of
  // squared deviations from their mean, m the adjustments in which it kept observations, at least
  // 2): its rotation in the rig along the worst axis (deg) and the direction of its centre from
  // camera 0's (deg). nullopt for camera 0 and cameras without a pose in the solution or with
  // fewer than 2 such adjustments.
  PerCamera<double> rotation_std_deg;
  PerCamera<double> direction_std_deg;
};

// Runs the adjustment once per posed frame (or run of frames) without its observations, from the
// solution, side by side (each single-threaded, so the result does not depend on the threads). A
// left-out frame 0 hands the gauge to the first posed frame of the next run, held where the
// solution put it.
FrameJackknife JackknifeOverFrames(const RigAdjustmentProblem& problem);

}  // namespace rigsim
