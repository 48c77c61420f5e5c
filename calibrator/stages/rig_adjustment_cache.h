// The bundle adjustments of the rig stage's rounds, kept so that a round does not solve again what
// an earlier round solved. The rounds (rig_calibration.cc) make the rig again after each pair they
// leave out; a round that only leaves a pair's baseline direction out keeps that pair's matches,
// so the tracks, and the start positions from the tracks, are those of the round before: the same
// solve on the same inputs (BENCHMARKS.md measures it on the six-camera twin).
//
// An adjustment is given back only when everything it reads is identical: the cameras, options
// and capture timing by value (their operator==), the tracks with the keypoints they observe, the
// start poses and the scale camera bit for bit. MultiFrameRigBundleAdjust is single-threaded and
// deterministic, so a kept result is the very bits a new solve would give.
#pragma once

#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "calibrator/estimators/multi_frame_rig.h"
#include "calibrator/model/rig_state.h"
#include "calibrator/model/tracks.h"
#include "geometry/camera.h"

namespace rigsim {

// What the adjustment from one start reads (MultiFrameRigBundleAdjust's arguments), by reference:
// the caller keeps them alive for the call.
struct StartAdjustmentInputs {
  const std::vector<Camera>& cameras;
  const FrameKeypoints& keypoints;
  const std::vector<ViewTrack>& tracks;
  const RigPoses& start;
  int scale_camera = -1;
  const RigBundleAdjustmentOptions& options;
  bool hold_frames = false;
  const CaptureTiming* timing = nullptr;
};

// One start's adjustment, and how well its poses explain the tracks (TruncatedReprojectionCost
// with the options' max_reprojection_error_px and min_triangulation_angle_deg).
struct AdjustedStart {
  MultiFrameBundleAdjustmentResult ba;
  double cost = 0.0;
  int cost_observations = 0;
  bool reused = false;  // given back by RigAdjustmentCache, not solved
};

// Solves the adjustment from one start and measures its cost.
AdjustedStart AdjustStart(const StartAdjustmentInputs& in);

class RigAdjustmentCache {
 public:
  // AdjustStart(in), or a copy of the result of an earlier call on identical inputs (`reused` set).
  // Safe to call from several threads at once (the starts of a round run side by side).
  AdjustedStart Adjust(const StartAdjustmentInputs& in);

 private:
  // The inputs of a solved adjustment: those compared by value, and the rest as their bits.
  struct Key {
    std::vector<Camera> cameras;
    RigBundleAdjustmentOptions options;
    std::optional<CaptureTiming> timing;
    std::string bits;

    bool operator==(const Key&) const = default;
  };
  struct Entry {
    Key key;
    AdjustedStart adjusted;
  };
  // The key of `in`; nullopt when a track names a keypoint that is not there (then the solver
  // alone says what it makes of that, uncached).
  static std::optional<Key> KeyOf(const StartAdjustmentInputs& in);

  std::mutex mutex_;
  std::vector<Entry> entries_;
};

}  // namespace rigsim
