// Which views to match across time: camera a at frame t with camera b at frame t' != t, where the
// rig's motion brings b to look where a looked. Chosen from what is already estimated, not by
// matching all N^2 F^2 pairs of views:
//  - when both cameras' rotations in the rig and both frames' rig rotations are known: the
//    predicted overlap of the two views (a grid of a's pixels carried at the scene's depth, or at
//    infinity without positions, into b's image), the best few per camera pair, spread over the
//    path;
//  - when the two cameras' relative rotation is not known yet (nothing links them): a search, one
//    view pair per bin of the rig's turn between the two frames (a camera's mounting shows as the
//    turn at which its views meet another's), the pair the rig moved least between; a cheap screen
//    (calibrator/stages/pairwise.h) keeps the ones that share a view.
// Camera pairs include a camera with itself (a loop brings it back where it was) when its rotation
// is known, for frames at least min_frame_gap apart.
#pragma once

#include <optional>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "calibrator/model/rig_state.h"
#include "geometry/camera.h"

namespace rigsim {

struct CrossTimeCandidateOptions {
  // Predicted: view pairs whose predicted overlap is at least this fraction of a's image.
  double min_predicted_overlap = 0.25;
  // Predicted: at most this many view pairs per camera pair, no two within one frame of each other
  // in both views.
  int max_per_camera_pair = 4;
  // Search: the width (deg) of a bin of the rig's turn between two frames, per axis of its rotation
  // vector, and at most this many bins per camera pair (the smallest turns first).
  double turn_bin_deg = 10.0;
  int max_search_per_camera_pair = 48;
  // A camera with itself: frames at least this far apart (consecutive ones are temporal pairs).
  int min_frame_gap = 2;

  // Throws std::invalid_argument naming the first bad field.
  void Check() const;
};

struct CrossTimeCandidate {
  int cam_a = -1, frame_a = -1;
  int cam_b = -1, frame_b = -1;
  // The predicted overlap (fraction of a's image seen by b); nullopt for a search candidate.
  std::optional<double> predicted_overlap;
};

struct CrossTimeCandidateInputs {
  std::vector<Camera> cameras;
  // Per camera (cam_from_rig) and per frame (rig_from_world); nullopt where not known.
  PerCamera<Eigen::Quaterniond> cam_from_rig;
  PerFrame<Eigen::Quaterniond> rig_from_world;
  // Optional positions, in one unit: the rig's centre in the world per frame, and the typical
  // depth of the scene from the cameras. Without them the views are compared at infinity.
  PerFrame<Eigen::Vector3d> rig_centre_in_world;
  std::optional<double> scene_depth;
};

// Candidates in a deterministic order (camera pair, then predicted ones best first, then search
// ones by turn). Throws std::invalid_argument on sizes that do not match.
std::vector<CrossTimeCandidate> SelectCrossTimeCandidates(const CrossTimeCandidateInputs& inputs,
                                                          const CrossTimeCandidateOptions& options);

// The predicted overlap of view (a, t) with (b, t') as SelectCrossTimeCandidates computes it;
// nullopt when a rotation is unknown.
std::optional<double> PredictedViewOverlap(const CrossTimeCandidateInputs& inputs, int cam_a, int frame_a, int cam_b,
                                           int frame_b);

}  // namespace rigsim
