// Which of its possible poses each camera's step between frames takes, decided by the rig: between
// the same two frames every camera of a rigid rig turns by the rig's turn, seen through its mounting
// (R_ck = X_c R_k X_c^T, hand_eye.h). One pair cannot decide what the rig can:
//  - a planar pair (a facade filling the view) fits two poses (TwoViewEstimate::planar_alternatives),
//    and the essential matrix's fit may take the wrong one, several degrees off;
//  - a pair whose matches agree on a wrong pose has no alternative but disagrees with the others.
// Each camera's mounting rotation (unless known) is found against camera 0's steps by RANSAC over
// pairs of steps (any candidate pose of either camera), then the rig's turn at each step is the one most cameras'
// candidates agree on, and each step takes its candidate nearest that turn.
//
// Conventions: geometry/rigid3.h; a step k is cam(k+1)_from_cam(k); angles in degrees in options.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "calibrator/model/rig_state.h"
#include "calibrator/model/view_graph.h"

namespace rigsim {

struct RigTurnOptions {
  // A step agrees with the rig when its rotation is within this (deg) of the rig's turn seen
  // through the camera's mounting: above the errors of right pairs (under 1.6 deg on the street at
  // 640x360), below the planar alternatives' (2 deg and more).
  double max_disagreement_deg = 2.0;
  // Steps that turned less than this (deg) give no axis: they neither make nor test a mounting.
  double min_turn_deg = 1.0;
  // A camera's mounting needs at least this many steps agreeing with camera 0's.
  int min_agreeing_steps = 3;

  // Throws std::invalid_argument naming the first bad field.
  void Check() const;
};

enum class StepChoice {
  kNone,         // no successful pair at this step (the rig's turn still gives its rotation)
  kUndecided,    // the rig's turn at this step, or the camera's mounting, is not known: kept as it is
  kAgrees,       // the pair's own pose agrees with the rig
  kAlternative,  // the pair's planar alternative agrees with the rig; its own pose does not
  kDisagrees,    // no pose of the pair agrees with the rig
};

struct RigTurns {
  // Per camera: its mounting rotation (cam_from_rig, camera 0 the identity): the known one, else
  // found, nullopt when fewer than min_agreeing_steps of its steps agree with camera 0's. With a planar motion its turn about the
  // rig's axis is arbitrary (every step's rotation commutes with it): a test, not a result.
  PerCamera<Eigen::Quaterniond> cam_from_rig;
  // Per step k (frames k, k+1): the rig's turn rig(k+1)_from_rig(k) in camera 0's axes, nullopt when
  // fewer than two cameras agree on one.
  PerFrame<Eigen::Quaterniond> rig_turn;
  // Per frame: the rig's rotation rig(k)_from_rig(0), chained through rig_turn, or camera 0's own
  // step where the rig's turn is not known; nullopt from the first step neither gives.
  PerFrame<Eigen::Quaterniond> rig_from_world;
  // [camera][step]: what the step's pair is, against the rig.
  std::vector<std::vector<StepChoice>> choice;
  // [camera][step]: the camera's rotation over the step: its pair's pose that agrees with the rig;
  // the rig's turn seen through its mounting where no pose agrees or it has no pair; the pair's own
  // where undecided; nullopt without a pair or a rig's turn.
  std::vector<PerFrame<Eigen::Quaterniond>> step_rotation;
  // The temporal pairs with the pose the rig agrees with (a planar alternative swapped in); a pair no
  // pose of which agrees has its pose left out (TemporalPairEstimate::pose_left_out), its matches kept.
  std::vector<TemporalPairEstimate> temporal;
  int alternatives_taken = 0;
  int pairs_disagreeing = 0;
};

// `temporal` as the rig stages take it (RigObservations::temporal); `known_cam_from_rig` (one per
// camera, nullopt where unknown) are mountings already known (from same-instant pairs): they are
// used as they are, the others found from the steps.
RigTurns ResolveStepsByTheRig(const std::vector<TemporalPairEstimate>& temporal,
                              const PerCamera<Eigen::Quaterniond>& known_cam_from_rig, int num_frames,
                              const RigTurnOptions& options);

}  // namespace rigsim
