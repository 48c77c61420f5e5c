// The rig stage, in memory: from the pairwise stage's observations (model/rig_observations.h) to
// every camera's cam_from_rig. No file is read and no truth is seen.
//
// Steps: view graph (model/view_graph.h) -> robust rotation averaging
// (estimators/rotation_averaging.h; with motion links every rotation jointly, rig_motion_links.h)
// -> rig rotation per frame from the temporal pairs -> tracks over all views (model/tracks.h) ->
// camera and rig positions over the tracks (estimators/rig_positions.h) -> multi-frame bundle
// adjustment from every start (estimators/multi_frame_rig.h) -> capture times checked or estimated
// (rig_capture_times.h). The rig's motion links the scales of the camera pairs, so a ring where only
// neighbours overlap (a chain, not parallel rigid) is determined once it moves. Without temporal
// pairs (one frame, or none given) every frame is an independent capture of a static rig and only
// same-frame tracks constrain the positions. Whether the motion stage's links are added, and which
// pass is kept, is the controller's (calibrator/motion_passes.h).
//
// Gauge: camera 0 is the rig frame (its cam_from_rig is the identity); frame 0's rig frame is the
// world. Only the cameras the pairs reach from camera 0 get rotations; every other camera is
// reported "not connected: <reason>" and gets no pose, never a guessed one. A camera with a
// rotation whose position the data do not determine (e.g. a chain of cameras and one frame) is
// reported "rotation only: <reason>": result.cam_from_rig_rotation has its rotation, the rig
// (and rig.json) has no cam_from_rig for it: there is no made-up translation.
// Scale: images fix none. Without a known distance the centre of the first calibrated camera
// after camera 0 is at distance 1 ("unit scale"); with one, the two named cameras' centres are
// that many metres apart ("metric").
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "calibrator/model/rig_observations.h"
#include "calibrator/model/rig_state.h"
#include "calibrator/stages/known_distance_scale.h"
#include "calibrator/stages/rig_options.h"
#include "calibrator/stages/rig_result.h"

namespace rigsim {

// The rig stages on given observations (no truth, no pairwise report). Throws
// std::invalid_argument on inconsistent observations or a known distance naming an unknown camera.
RigCalibrationResult EstimateRig(const RigObservations& observations, const RigCalibrationOptions& options);

struct RigRounds;  // where the pair-rejection rounds stand (rig_calibration.cc)

// Where EstimateRigUnlessUnplaced stopped. Exists so that the motion stage can run before a full
// pass whose result it would replace.
struct RigPreCheck {
  // The pair-rejection round (0: the first; r: after r pairs left out, max_rejected_pairs) whose
  // early stages (rotation averaging, the rig's motion, tracks, initial positions) it checked.
  int round = 0;
  // Per camera: rotation averaging gives it a rotation and some start of the bundle adjustment a
  // position. A camera without is left without a full pose, unless a pair a later round rejects made
  // rotation averaging leave it out; one with may still lose its position in the bundle adjustment
  // (RigCalibrationOptions::max_direction_std_deg, ambiguous starts).
  std::vector<char> may_be_placed;
  // Per camera: cam_from_rig's rotation from that round's rotation averaging; nullopt where none.
  PerCamera<Eigen::Quaterniond> cam_from_rig_rotation;
  // The stage times of what ran until the stop (every earlier round whole, rig_passes 0).
  RigWork work;
  // The rounds completed before the stop, for EstimateRigFrom.
  std::shared_ptr<const RigRounds> rounds;

  bool SomeCameraWithoutFullPose() const;
};

// EstimateRig, stopped before the bundle adjustment of the first round whose early stages leave a
// camera without a rotation or a start position: then nullopt, and `stop` says where and why.
// Throws like EstimateRig.
std::optional<RigCalibrationResult> EstimateRigUnlessUnplaced(const RigObservations& observations,
                                                              const RigCalibrationOptions& options, RigPreCheck* stop);

// EstimateRig on the same observations and options, resumed where EstimateRigUnlessUnplaced
// stopped (`stop`): the rounds it completed are not run again, and their work is in stop.work,
// not in the result.
RigCalibrationResult EstimateRigFrom(const RigObservations& observations, const RigCalibrationOptions& options,
                                     const RigPreCheck& stop);

// The bundle adjustment's counts and reprojection figures into `result`.
void SetAdjustmentSummary(const MultiFrameBundleAdjustmentResult& ba, RigCalibrationResult* result);

// The intrinsics of the cameras `ba` refined (RigBundleAdjustmentOptions::refine_intrinsics) into
// `result`'s rig, with their given values and standard deviations (RigCameraStats::intrinsics).
void SetRefinedIntrinsics(const RigObservations& obs, const RigCalibrationOptions& options,
                          const MultiFrameBundleAdjustmentResult& ba, RigCalibrationResult* result);

}  // namespace rigsim
