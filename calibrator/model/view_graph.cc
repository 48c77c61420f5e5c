#include "calibrator/model/view_graph.h"

#include <stdexcept>

#include "calibrator/model/union_find.h"

namespace rigsim {

void ViewGraphOptions::Check() const {
  if (min_inliers < 5) throw std::invalid_argument("ViewGraphOptions: min_inliers must be >= 5");
}

void ViewGraph::Deactivate(int edge, const std::string& reason) {
  ViewGraphEdge& e = edges.at(edge);
  if (!e.active) return;
  e.active = false;
  e.inactive_reason = reason;
}

ViewGraph BuildViewGraph(int num_cameras, const std::vector<PairEstimate>& pairs, const ViewGraphOptions& options) {
  options.Check();
  ViewGraph graph;
  graph.num_cameras = num_cameras;
  for (const PairEstimate& p : pairs) {
    if (p.cam_a < 0 || p.cam_b < 0 || p.cam_a >= num_cameras || p.cam_b >= num_cameras || p.cam_a == p.cam_b) {
      throw std::invalid_argument("BuildViewGraph: pair (" + std::to_string(p.cam_a) + ", " + std::to_string(p.cam_b) +
                                  ") is not a pair of distinct cameras among " + std::to_string(num_cameras));
    }
    const TwoViewEstimate& tv = p.two_view;
    ViewGraphEdge e;
    // Store with cam_a < cam_b whatever the input order.
    const Rigid3d pose = p.cam_a < p.cam_b ? tv.cam_b_from_cam_a : tv.cam_b_from_cam_a.Inverse();
    e.cam_a = std::min(p.cam_a, p.cam_b);
    e.cam_b = std::max(p.cam_a, p.cam_b);
    e.rotation = pose.rotation;
    e.rotation_only = tv.rotation_only;
    if (!tv.rotation_only && pose.translation.norm() > 1e-12) {
      e.direction = pose.translation.normalized();
    } else {
      e.rotation_only = true;
    }
    e.weight = tv.num_inliers;
    if (!tv.success) {
      e.inactive_reason = "two-view failed: " + (tv.failure_reason.empty() ? std::string("unknown") : tv.failure_reason);
    } else if (tv.num_inliers < options.min_inliers) {
      e.inactive_reason =
          "too few inliers (" + std::to_string(tv.num_inliers) + " < " + std::to_string(options.min_inliers) + ")";
    } else {
      e.active = true;
    }
    graph.edges.push_back(std::move(e));
  }
  return graph;
}

std::vector<int> ConnectedComponents(const ViewGraph& graph, bool translation_only) {
  UnionFind components(graph.num_cameras);
  for (const ViewGraphEdge& e : graph.edges) {
    if (!e.active || (translation_only && e.rotation_only)) continue;
    components.Join(e.cam_a, e.cam_b);
  }
  // The root is the smallest id: the label is the component's smallest camera.
  std::vector<int> label(graph.num_cameras);
  for (int c = 0; c < graph.num_cameras; ++c) label[c] = components.Find(c);
  return label;
}

std::string NotConnectedReason(const ViewGraph& graph, int camera, const std::vector<char>& reached,
                               const std::vector<std::string>& camera_names) {
  auto name = [&](int c) {
    return c < static_cast<int>(camera_names.size()) ? camera_names[c] : "camera " + std::to_string(c);
  };
  std::string why;
  for (const ViewGraphEdge& e : graph.edges) {
    if (e.cam_a != camera && e.cam_b != camera) continue;
    const int other = e.cam_a == camera ? e.cam_b : e.cam_a;
    if (!reached[other]) continue;
    why += (why.empty() ? "" : "; ") + name(e.cam_a) + "-" + name(e.cam_b) + ": " +
           (e.active ? std::string("active (") + (e.rotation_only ? "rotation only" : "usable") + ")"
                     : e.inactive_reason);
  }
  if (why.empty()) why = "no pair with any calibrated camera";
  return why;
}

}  // namespace rigsim
