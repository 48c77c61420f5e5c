// What the rig stages consume, independent of images: the pairwise outcome, its inliers, the
// frames' times and, once the motion stage ran, its links.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "calibrator/model/correspondences.h"
#include "calibrator/model/rig_state.h"
#include "calibrator/model/view_graph.h"
#include "geometry/camera.h"

namespace rigsim {

// What the rig stages consume, independent of images: the pairwise outcome and its inliers.
struct RigObservations {
  std::vector<std::string> camera_names;
  std::vector<Camera> cameras;
  FrameKeypoints keypoints;          // [frame][camera][keypoint]
  std::vector<PairEstimate> pairs;   // one per camera pair
  std::vector<PairMatches> inliers;  // the same pairs' two-view inliers per frame (empty when failed)
  // The same pairs' matches per frame, the inliers' superset; may be empty (then a pair cannot be
  // estimated again, e.g. with refined intrinsics).
  std::vector<PairMatches> matches;
  // Each camera between consecutive frames (pairwise.h PairwiseMatchData::temporal). Empty: the
  // frames are independent captures of a static rig (no rig motion is estimated).
  std::vector<TemporalPairEstimate> temporal;
  // Each frame's timestamp (s); empty when unknown (then capture times are not modelled).
  std::vector<double> frame_times_s;
  // Per camera: its rolling shutter reads the bottom row first; empty: every one top to bottom.
  std::vector<char> readout_bottom_to_top;
  // From the rig's motion (motion_links.h); empty unless that stage ran. View pairs of cameras at
  // different frames; per camera the start of its rotation in the rig (nullopt: none), the rotation
  // hand-eye calibration determined (hand_eye.h kSolved; nullopt otherwise), and the turn axis of a
  // planar motion (in the rig) along which its motion does not fix its centre.
  std::vector<CrossTimePairEstimate> cross_time;
  PerCamera<Eigen::Quaterniond> rotation_start;
  PerCamera<Eigen::Quaterniond> hand_eye_rotation;
  PerCamera<Eigen::Vector3d> open_axis;

  bool HasMotionLinks() const { return !rotation_start.empty(); }
};

}  // namespace rigsim
