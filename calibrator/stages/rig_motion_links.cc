#include "calibrator/stages/rig_motion_links.h"

#include <algorithm>
#include <string>

#include "calibrator/model/rig_state.h"
#include "common/format.h"

namespace rigsim {
namespace {

// Cameras joined with camera 0 by active same-instant edges of `graph`.
std::vector<char> ReachedByEdges(const ViewGraph& graph, int n) {
  std::vector<char> reached(n, 0);
  reached[0] = 1;
  for (bool grew = true; grew;) {
    grew = false;
    for (const ViewGraphEdge& e : graph.edges) {
      if (!e.active || reached[e.cam_a] == reached[e.cam_b]) continue;
      reached[e.cam_a] = reached[e.cam_b] = 1;
      grew = true;
    }
  }
  return reached;
}

// One joint averaging of every rotation, leaving out the cross-time pairs of `dropped` cameras.
JointRotations AverageJointly(const RigObservations& obs, const ViewGraph& graph, const std::vector<char>& dropped,
                              const MotionLinkOptions& options) {
  const int n = static_cast<int>(obs.cameras.size());
  const int num_frames = static_cast<int>(obs.keypoints.size());
  std::vector<ViewPairRotation> measurements;
  for (const ViewGraphEdge& e : graph.edges) {
    if (e.active) measurements.push_back({e.cam_a, e.cam_b, -1, -1, e.rotation, std::max(e.weight, 1)});
  }
  for (const TemporalPairEstimate& t : obs.temporal) {
    if (!t.PoseUsable()) continue;
    measurements.push_back({t.camera, t.camera, t.frame, t.frame + 1, t.two_view.cam_b_from_cam_a.rotation,
                            std::max(t.two_view.num_inliers, 1)});
  }
  std::vector<int> measurement_of(obs.cross_time.size(), -1);  // per cross-time pair
  for (size_t i = 0; i < obs.cross_time.size(); ++i) {
    const CrossTimePairEstimate& x = obs.cross_time[i];
    if (dropped[x.cam_a] || dropped[x.cam_b]) continue;
    measurement_of[i] = static_cast<int>(measurements.size());
    measurements.push_back({x.cam_a, x.cam_b, x.frame_a, x.frame_b, x.two_view.cam_b_from_cam_a.rotation,
                            std::max(x.two_view.num_inliers, 1)});
  }
  PerCamera<Eigen::Quaterniond> starts = obs.rotation_start;
  for (int c = 0; c < n && !starts.empty(); ++c) {
    if (dropped[c]) starts[c].reset();
  }
  JointRotations out;
  out.rotations = AverageRigRotations(n, num_frames, measurements, starts, options.rotation_averaging);
  for (int c = 0; c < n; ++c) {
    if (dropped[c]) out.rotations.cam_from_rig[c].reset();
  }
  const auto& q = out.rotations.cam_from_rig;
  const auto& r = out.rotations.rig_from_world;
  for (size_t i = 0; i < obs.cross_time.size(); ++i) {
    const CrossTimePairEstimate& x = obs.cross_time[i];
    const int m = measurement_of[i];
    out.cross_time_used.push_back(m >= 0 && !out.rotations.outlier[m] && q[x.cam_a] && q[x.cam_b] && r[x.frame_a] &&
                                  r[x.frame_b]);
  }
  return out;
}

// Marks in `dropped` the cameras outside `reached` whose rotation no two things agree on: hand-eye
// within MotionLinkOptions::max_hand_eye_disagreement_deg counts as two, each used cross-time pair
// with another camera still kept as one; and those no used pair joins with an anchored camera.
void DropUnsupportedCameras(const RigObservations& obs, const std::vector<char>& reached,
                            const MotionLinkOptions& options, JointRotations* joint, std::vector<char>* dropped) {
  const int n = static_cast<int>(obs.cameras.size());
  auto& q = joint->rotations.cam_from_rig;
  for (bool changed = true; changed;) {
    changed = false;
    for (int c = 1; c < n; ++c) {
      if (reached[c] || !q[c]) continue;
      int support = 0;
      const auto& he = obs.hand_eye_rotation.empty() ? std::nullopt : obs.hand_eye_rotation[c];
      if (he && RotationDifferenceDeg(*he, *q[c]) <= options.max_hand_eye_disagreement_deg) support += 2;
      for (size_t i = 0; i < obs.cross_time.size(); ++i) {
        const CrossTimePairEstimate& x = obs.cross_time[i];
        const int other = x.cam_a == c ? x.cam_b : x.cam_b == c ? x.cam_a : c;
        support += joint->cross_time_used[i] && other != c && q[other];
      }
      if (support >= 2) continue;
      q[c].reset();
      (*dropped)[c] = 1;
      changed = true;
      for (size_t i = 0; i < obs.cross_time.size(); ++i) {
        if (obs.cross_time[i].cam_a == c || obs.cross_time[i].cam_b == c) joint->cross_time_used[i] = 0;
      }
    }
  }
  // Two cameras that agree only with each other hang on hand-eye starts that did not determine
  // them: kept are the cameras used cross-time pairs join with camera 0's part or hand-eye's.
  std::vector<char> anchored = reached;
  for (int c = 1; c < n; ++c) {
    const auto& he = obs.hand_eye_rotation.empty() ? std::nullopt : obs.hand_eye_rotation[c];
    if (q[c] && he && RotationDifferenceDeg(*he, *q[c]) <= options.max_hand_eye_disagreement_deg) anchored[c] = 1;
  }
  for (bool grew = true; grew;) {
    grew = false;
    for (size_t i = 0; i < obs.cross_time.size(); ++i) {
      const CrossTimePairEstimate& x = obs.cross_time[i];
      if (!joint->cross_time_used[i] || anchored[x.cam_a] == anchored[x.cam_b]) continue;
      anchored[x.cam_a] = anchored[x.cam_b] = 1;
      grew = true;
    }
  }
  for (int c = 1; c < n; ++c) {
    if (anchored[c] || !q[c]) continue;
    q[c].reset();
    (*dropped)[c] = 1;
  }
  for (size_t i = 0; i < obs.cross_time.size(); ++i) {
    const CrossTimePairEstimate& x = obs.cross_time[i];
    if (!q[x.cam_a] || !q[x.cam_b]) joint->cross_time_used[i] = 0;
  }
}
}  // namespace

JointRotations AverageRotationsWithMotionLinks(const RigObservations& obs, const ViewGraph& graph,
                                               const MotionLinkOptions& options) {
  const int n = static_cast<int>(obs.cameras.size());
  const std::vector<char> reached = ReachedByEdges(graph, n);
  std::vector<char> dropped(n, 0);  // cameras without two agreeing supports
  JointRotations out;
  for (int round = 0; round < 2; ++round) {
    out = AverageJointly(obs, graph, dropped, options);
    std::vector<char> more = dropped;
    DropUnsupportedCameras(obs, reached, options, &out, &more);
    if (more == dropped) break;
    dropped = more;
  }
  return out;
}

PerCamera<Eigen::Vector3d> HeldCentreAxes(const RigObservations& obs, const std::vector<ViewTrack>& tracks) {
  const int n = static_cast<int>(obs.cameras.size());
  PerCamera<Eigen::Vector3d> held(n);
  if (obs.open_axis.empty()) return held;
  std::vector<char> shares(n, 0);  // a track joins the camera with another one
  for (const ViewTrack& t : tracks) {
    for (const ViewObservation& o : t.observations) {
      if (o.camera != t.observations[0].camera) {
        for (const ViewObservation& p : t.observations) shares[p.camera] = 1;
        break;
      }
    }
  }
  for (int c = 1; c < n; ++c) {
    if (obs.open_axis[c] && !shares[c]) held[c] = obs.open_axis[c];
  }
  return held;
}

std::string OpenAxisReason(const Eigen::Vector3d& axis) {
  return "its offset along the turn axis of the rig's planar motion (" + Fixed(axis.x(), 2) + ", " +
         Fixed(axis.y(), 2) + ", " + Fixed(axis.z(), 2) +
         " in the rig: its height when the rig turns about the vertical) is not determined: no point joins it with "
         "another camera, and a motion about one axis leaves it open; to place it: a path that also pitches or rolls, "
         "or more overlap with a placed camera";
}

double InterCameraWeight(const std::vector<ViewTrack>& tracks, double max_weight) {
  double all = 0.0, shared = 0.0;
  for (const ViewTrack& t : tracks) {
    all += t.observations.size();
    const bool joins = std::any_of(t.observations.begin(), t.observations.end(),
                                   [&](const ViewObservation& o) { return o.camera != t.observations[0].camera; });
    if (joins) shared += t.observations.size();
  }
  if (shared <= 0.0) return 1.0;
  return std::clamp(0.25 * all / shared, 1.0, max_weight);
}

}  // namespace rigsim
