// Hand-eye calibration of rig cameras from their own motions (AX = XB), and what those motions
// leave undetermined.
//
// Each camera's trajectory is known on its own (calibrator/camera_trajectory.h): its pose at every
// frame relative to its pose at frame 0, with a length unit of its own. The reference camera's
// trajectory is the rig's: P_k = rig(k)_from_rig(0), camera 0 being the rig frame. For camera c with
// X = cam_from_rig (rotation R_X, centre o in the rig):
//   rotation    R_ck = R_X R_k R_X^T                 the axis of c's turn is R_X times the rig's
//   centre      d_ck = s_c R_X (C_k + (R_k^T - I) o)  c's centre at frame k in its frame-0 axes
// (R_k, C_k: the rig's rotation and centre at frame k; s_c: c's unknown unit of length). Given R_X
// the centre equations are linear in (1 / s_c, o).
//
// What the motion determines:
//  - rotations about two or more axes: R_X from the axes (weighted Kabsch), and o;
//  - rotations about one axis only (planar motion, a vehicle on flat ground): R_X's turn about that
//    axis is fixed by the centres (searched), and o along the axis is not determined at all: every
//    R_k^T - I annihilates it. It is reported, and set to zero in the estimate, never guessed;
//  - no rotation (a straight path): neither R_X's turn about the path nor o; nothing is estimated.
// Conventions: geometry/rigid3.h; angles in degrees at the interface.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "calibrator/model/rig_state.h"
#include "geometry/rigid3.h"

namespace rigsim {

// How a trajectory turns, which decides what hand-eye calibration can recover.
enum class MotionKind {
  kStraight,  // no turn between two frames beyond HandEyeOptions::min_rotation_deg
  kPlanar,    // rotations about one axis (HandEyeOptions::max_planar_axis_spread)
  kGeneral,   // rotations about two or more axes
};

// "straight", "planar", "general".
const char* MotionKindName(MotionKind kind);

struct MotionClass {
  MotionKind kind = MotionKind::kStraight;
  // The mean rotation axis (unit, reference-camera frame at frame 0) for planar and general motions;
  // zero for a straight one.
  Eigen::Vector3d axis = Eigen::Vector3d::Zero();
  double max_rotation_deg = 0.0;  // the largest turn between two frames
  // sqrt(e2 / e1) of the weighted scatter of the rotation vectors: 0 for rotations about one axis.
  double axis_spread = 0.0;
};

struct HandEyeOptions {
  // Frames that turned less than this from frame 0 do not count as rotations (their axis is noise).
  double min_rotation_deg = 1.0;
  // A motion whose rotation vectors spread less than this across their main axis (sqrt of the
  // ratio of the scatter's two largest eigenvalues) is planar: its off-axis turn is too small to fix
  // a camera's turn about the axis, which the centres then fix.
  double max_planar_axis_spread = 0.2;
  // Search step (deg) of the turn about the axis of a planar motion; refined around the best.
  double planar_search_step_deg = 1.0;
  // A camera whose turns differ from the rig's (moved into it by the best mounting) by more than
  // this RMS (deg) is not explained by one rigid mounting: reported inconsistent, not solved.
  double max_rotation_rms_deg = 2.0;
  // A camera whose rotation in the rig the fit leaves more uncertain than this (standard deviation,
  // deg) is reported kRotationUndetermined: one axis at a constant turn rate (a circle) trades a
  // turn of the camera about the axis against a shift of its centre.
  double max_rotation_std_deg = 1.0;
  // The noise the joint fit of rotations and centres weighs them by: of a camera's rotation at a
  // frame (deg), and of its centre relative to the path's extent. Only their ratio matters to the
  // estimate; the standard deviations are rescaled by the residuals.
  double rotation_sigma_deg = 0.1;
  double centre_sigma = 0.01;

  // Throws std::invalid_argument naming the first bad field.
  void Check() const;
};

// What a trajectory of one camera says of it: per frame, cam(k)_from_cam(0) with the camera's own
// length unit; nullopt for a frame it was not tracked at. Frame 0 is the identity.
using CameraTrajectory = PerFrame<Rigid3d>;

enum class HandEyeStatus {
  kSolved,            // rotation and centre (the centre possibly but for one axis: undetermined_axis)
  kReference,         // camera 0: the rig frame
  kStraightMotion,    // the rig did not turn: nothing is determined
  kTooFewFrames,      // fewer than two turned frames shared with the reference
  kInconsistent,      // the camera's turns do not match the rig's (another motion, or wrong matches)
  kRotationUndetermined,  // solved, but the motion leaves its turn about the rig's axis open
};

struct HandEyeCamera {
  HandEyeStatus status = HandEyeStatus::kTooFewFrames;
  std::string reason;  // for people; empty when solved
  // With kSolved and kReference: cam_from_rig, its translation in the reference trajectory's unit;
  // when undetermined_axis is set, the centre's component along it is zero (not estimated). With
  // kRotationUndetermined: the best fit, a start for an estimator that brings more data (matches
  // with other cameras), never a result.
  std::optional<Rigid3d> cam_from_rig;
  // Unit direction in the rig along which the camera's centre is not determined (planar motion).
  std::optional<Eigen::Vector3d> undetermined_axis;
  // The camera's length unit in the reference's (s_c above); > 0 when solved.
  double scale = 0.0;
  int frames_used = 0;
  // RMS over the frames used of the angle between the camera's turn and the rig's turn moved into
  // the camera by R_X (deg), and of the centre residual over the path length: how well one mounting
  // explains the camera's whole trajectory.
  double rotation_rms_deg = 0.0;
  double centre_rms = 0.0;
  // Standard deviation of the rotation in the rig (deg, the worst direction) from the fit.
  double rotation_std_deg = 0.0;
};

struct HandEyeResult {
  MotionClass motion;
  std::vector<HandEyeCamera> cameras;  // one per input trajectory; camera 0 is the reference
};

// Classifies the reference trajectory's rotations.
MotionClass ClassifyMotion(const CameraTrajectory& reference, const HandEyeOptions& options);

// trajectories[0] is the reference camera's (the rig's); every trajectory has one entry per frame.
// Throws std::invalid_argument when they differ in length or frame 0 is missing.
HandEyeResult SolveHandEye(const std::vector<CameraTrajectory>& trajectories, const HandEyeOptions& options);

}  // namespace rigsim
