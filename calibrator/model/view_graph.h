// The view graph of a rig: one node per camera, one edge per camera pair, carrying the pair's
// two-view estimate (relative rotation, unit translation direction unless rotation-only) and its
// inlier count as the weight.
//
// Every pair stays in the graph, also the failed ones: an edge is either active (used by the rig
// stages) or inactive with the reason, so that a camera left out of the calibration can always be
// reported with why ("not connected: ...") instead of being guessed.
//
// Conventions: an edge's pose is cam_b_from_cam_a (two_view.h), with cam_a < cam_b; for cameras
// with rotations R_a = cam_a_from_rig, R_b: R_ab = R_b R_a^T.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "calibrator/model/two_view_geometry.h"
#include "geometry/rigid3.h"

namespace rigsim {

// One camera pair and its two-view outcome (two_view.h), cameras by index.
struct PairEstimate {
  int cam_a = -1;
  int cam_b = -1;
  TwoViewEstimate two_view;
};

// One camera's two-view outcome between consecutive frames k and k+1: the rig's motion seen by
// that camera. `two_view.cam_b_from_cam_a` is the camera at frame k+1 from the camera at frame k
// (unit translation, zero when rotation-only).
struct TemporalPairEstimate {
  int camera = -1;
  int frame = -1;  // k; the pair is (k, k+1)
  TwoViewEstimate two_view;
  // Two-view inliers: (keypoint index in frame k, in frame k+1); empty when the estimate failed.
  std::vector<std::pair<int, int>> inliers;
  // Every match the estimate saw (the inliers' superset), in the same form.
  std::vector<std::pair<int, int>> matches;
  // Why the pair's pose is not used, when the rig's turns disagree with every pose its matches allow
  // (calibrator/rig_turns.h); its inliers still make tracks. Empty otherwise.
  std::string pose_left_out;

  // The pose may be used: the estimate succeeded and the rig does not contradict it.
  bool PoseUsable() const { return two_view.success && pose_left_out.empty(); }
};

// A view pair beyond the same-instant pairs: camera a at frame_a with camera b at frame_b. From the
// motion stage (calibrator/motion_links.h) at different frames, where the rig's motion brought b to
// look where a looked; cam_a == cam_b is a camera back where it was (a loop). From registration
// through tracks (stages/track_registration.h) also at one frame: a registered camera's inliers
// with a placed view. `two_view.cam_b_from_cam_a` is view (b, frame_b) from view (a, frame_a).
struct CrossTimePairEstimate {
  int cam_a = -1, frame_a = -1;
  int cam_b = -1, frame_b = -1;
  TwoViewEstimate two_view;
  // Two-view inliers: (keypoint index in view a, in view b); empty when the estimate failed.
  std::vector<std::pair<int, int>> inliers;
};

struct ViewGraphOptions {
  // Successful pairs with fewer inliers are left inactive: a handful of inliers that happen to
  // agree is how a wrong pair (repeated texture, one plane) looks.
  int min_inliers = 30;

  // Throws std::invalid_argument naming the first bad field.
  void Check() const;
};

struct ViewGraphEdge {
  int cam_a = -1;
  int cam_b = -1;
  Eigen::Quaterniond rotation = Eigen::Quaterniond::Identity();  // of cam_b_from_cam_a
  Eigen::Vector3d direction = Eigen::Vector3d::Zero();  // unit translation of cam_b_from_cam_a; zero when rotation-only
  bool rotation_only = false;
  int weight = 0;  // inliers
  bool active = false;
  std::string inactive_reason;  // why the edge is not used; empty when active
};

struct ViewGraph {
  int num_cameras = 0;
  std::vector<ViewGraphEdge> edges;  // one per input pair, in input order

  // Marks an edge inactive, keeping the first reason given.
  void Deactivate(int edge, const std::string& reason);
};

// Throws std::invalid_argument when a pair names a camera out of range or itself.
ViewGraph BuildViewGraph(int num_cameras, const std::vector<PairEstimate>& pairs, const ViewGraphOptions& options);

// Connected components over the active edges (and, with translation_only, only the edges that
// have a translation direction): one label per camera, the smallest camera index of its component.
std::vector<int> ConnectedComponents(const ViewGraph& graph, bool translation_only = false);

// Why a camera outside `reached` (one flag per camera) is not connected: each of its pairs with a
// reached camera and why that pair is not used; or that it has no pair with them at all.
std::string NotConnectedReason(const ViewGraph& graph, int camera, const std::vector<char>& reached,
                               const std::vector<std::string>& camera_names);

}  // namespace rigsim
