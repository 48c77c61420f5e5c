// One camera's trajectory from its own images: the hand-eye start of a rig whose cameras share
// little or nothing of their views (hand_eye.h).
//
// Rotations are chained through the camera's steps between consecutive frames (rig_turns.h: its
// temporal pairs' poses as the rig decides between them); centres come from its tracks across frames
// (its temporal pairs' inliers) with those rotations (rig_positions.h EstimateTrajectoryCentres), in
// a unit of length of the camera's own. A frame the chain does not reach (a step without a rotation)
// and every frame after it has no pose.
#pragma once

#include <optional>
#include <vector>

#include <Eigen/Geometry>

#include "calibrator/estimators/hand_eye.h"
#include "calibrator/estimators/rig_positions.h"
#include "calibrator/model/correspondences.h"
#include "calibrator/model/rig_state.h"
#include "calibrator/model/view_graph.h"
#include "geometry/camera.h"

namespace rigsim {

// `camera_index` selects the camera's keypoints in `keypoints` ([frame][camera][keypoint]) and its
// pairs in `temporal` (the rig's temporal pairs, any order); `steps[k]` is its rotation
// cam(k+1)_from_cam(k) (RigTurns::step_rotation). Returns cam(k)_from_cam(0) per frame.
CameraTrajectory EstimateCameraTrajectory(const Camera& camera, int camera_index, const FrameKeypoints& keypoints,
                                          const std::vector<TemporalPairEstimate>& temporal,
                                          const PerFrame<Eigen::Quaterniond>& steps,
                                          const RigPositionOptions& options);

}  // namespace rigsim
