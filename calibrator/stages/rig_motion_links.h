// What the rig stage (rig_calibration.h) does with the motion stage's links (motion_links.h,
// RigObservations::HasMotionLinks): every rotation averaged jointly, centres held along the axis a
// planar motion leaves open, and the observations shared by two cameras weighed up.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "calibrator/estimators/multi_frame_rig.h"
#include "calibrator/estimators/rig_rotation_averaging.h"
#include "calibrator/model/rig_observations.h"
#include "calibrator/model/rig_state.h"
#include "calibrator/model/view_graph.h"
#include "calibrator/stages/rig_options.h"

namespace rigsim {

// Every rotation jointly (rig_rotation_averaging.h) from the active same-instant edges of `graph`,
// the successful temporal pairs and the cross-time pairs, started from obs.rotation_start; per
// cross-time pair whether it is used (not an outlier, both views with a rotation). A camera outside
// camera 0's part of `graph` without two agreeing supports (MotionLinkOptions::
// max_hand_eye_disagreement_deg) loses its rotation, and the rotations are averaged again without
// its cross-time pairs.
struct JointRotations {
  RigRotationAveragingResult rotations;
  std::vector<char> cross_time_used;
};
JointRotations AverageRotationsWithMotionLinks(const RigObservations& obs, const ViewGraph& graph,
                                               const MotionLinkOptions& options);

// Per camera: obs.open_axis where no track joins the camera with another one (its centre is then
// open along it, RigBundleAdjustmentOptions::held_centre_axis); nullopt otherwise.
PerCamera<Eigen::Vector3d> HeldCentreAxes(const RigObservations& obs, const std::vector<ViewTrack>& tracks);

// Why a camera's centre is open along `axis` (unit, in the rig) and what would fix it, in words.
std::string OpenAxisReason(const Eigen::Vector3d& axis);

// RigBundleAdjustmentOptions::inter_camera_weight for `tracks`: a quarter of the ratio of all
// observations to those of tracks that join two or more cameras, within [1, max_weight].
double InterCameraWeight(const std::vector<ViewTrack>& tracks, double max_weight);

}  // namespace rigsim
