// The geometry a teaching report draws, computed by the same camera models and alignment as the
// rest of rigsim so that the page can be checked against it:
//   - a camera's field of view through its lens (the image border's rays, or the border of the
//     lens's valid region where the border has no ray);
//   - the epipolar curve of a pixel: its ray from camera A, points along it projected into B
//     through B's lens model (a straight line for pinhole cameras, a curve with distortion);
//   - an estimate placed over the truth as `rigsim evaluate` aligns it (evaluation/rig_scores.h:
//     camera 0 is the gauge, the positions scaled by the fitted scale).
#pragma once

#include <optional>
#include <vector>

#include <Eigen/Core>

#include "calibrator/calibrate_rig.h"
#include "dataset/dataset.h"
#include "evaluation/rig_estimate.h"
#include "evaluation/rig_scores.h"
#include "geometry/camera.h"
#include "geometry/rig.h"
#include "geometry/rigid3.h"

namespace rigsim {

// Unit rays (camera frame) around the image border, clockwise from the top-left corner,
// `per_side` samples per side. A border pixel without a ray (a fisheye's corners) is replaced by
// the farthest pixel towards it from the principal point that has one.
std::vector<Eigen::Vector3d> FieldOfViewOutline(const Camera& camera, int per_side = 16);

// Depths (in the unit of `b_from_a`) at which EpipolarCurve samples a ray: log-spaced from
// `nearest` to `farthest`, `count` of them.
std::vector<double> EpipolarDepths(double nearest = 0.05, double farthest = 1.0e4, int count = 160);

// The pixel in B of the point at each depth (distance from A's centre along the ray of `px_a`),
// then of the point at infinity (the ray's direction alone) as the last entry; nullopt where B's
// lens does not image the point. Empty when `px_a` has no ray.
std::vector<std::optional<Eigen::Vector2d>> EpipolarCurve(const Camera& cam_a, const Eigen::Vector2d& px_a,
                                                          const Camera& cam_b, const Rigid3d& b_from_a,
                                                          const std::vector<double>& depths);

// A calibration's estimate as evaluate scores it (ScoreRig), placed in the truth's world.
struct AlignedEstimate {
  RigScores scores;
  // Per camera: cam_from_cam0 of the estimate with its translation scaled by scores.scale; for a
  // "rotation only" camera, the rotation with the true translation (its position is unknown);
  // nullopt for a camera without a rotation.
  std::vector<std::optional<Rigid3d>> cam_from_cam0;
  std::vector<char> rotation_only;
  // world_from_est_world: the estimate's world (camera 0 at frame 0) placed at the true camera
  // 0 of frame 0, lengths scaled by scores.scale (for the rig's trajectory and the points).
  Eigen::Matrix3d world_rotation = Eigen::Matrix3d::Identity();
  Eigen::Vector3d world_translation = Eigen::Vector3d::Zero();
  double scale = 1.0;

  // A point of the estimate's world in the truth's world.
  Eigen::Vector3d ToWorld(const Eigen::Vector3d& x_est) const {
    return world_rotation * (scale * x_est) + world_translation;
  }
};

// `truth` must have every cam_from_rig and `frames` frame 0's rig_from_world.
AlignedEstimate AlignToTruth(const RigCalibrationResult& result, const Rig& truth, const FramesFile& frames);

}  // namespace rigsim
