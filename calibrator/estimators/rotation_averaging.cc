#include "calibrator/estimators/rotation_averaging.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <queue>
#include <stdexcept>

#include <ceres/ceres.h>

#include "calibrator/estimators/cost_functions.h"
#include "calibrator/estimators/robust_rotation_fit.h"
#include "calibrator/model/rig_state.h"
#include "calibrator/model/union_find.h"

namespace rigsim {
namespace {

double AngleDeg(const Eigen::Quaterniond& q) {
  return RadToDeg(2.0 * std::atan2(q.vec().norm(), std::abs(q.w())));
}

// Edges of `graph` usable in this round: active and not yet rejected.
std::vector<int> UsableEdges(const ViewGraph& graph, const std::vector<char>& outlier) {
  std::vector<int> edges;
  for (int i = 0; i < static_cast<int>(graph.edges.size()); ++i) {
    if (graph.edges[i].active && !outlier[i]) edges.push_back(i);
  }
  return edges;
}

// Rotations of the cameras reached from `reference` along a maximum spanning tree (Prim's).
PerCamera<Eigen::Quaterniond> SpanningTreeRotations(const ViewGraph& graph,
                                                                     const std::vector<int>& edges, int reference,
                                                                     double loop_threshold_deg) {
  const int n = graph.num_cameras;
  std::map<std::pair<int, int>, int> edge_of;
  std::vector<std::vector<int>> incident(n);
  for (int i : edges) {
    edge_of[{graph.edges[i].cam_a, graph.edges[i].cam_b}] = i;
    incident[graph.edges[i].cam_a].push_back(i);
    incident[graph.edges[i].cam_b].push_back(i);
  }
  // Rotation cam_to_from_cam_from along an edge, whichever way round it is stored.
  auto along = [&](int e, int from) {
    const ViewGraphEdge& g = graph.edges[e];
    return g.cam_a == from ? g.rotation : g.rotation.conjugate();
  };
  // Consistent loops per edge.
  std::map<int, int> loops;
  for (int e : edges) {
    const int a = graph.edges[e].cam_a, b = graph.edges[e].cam_b;
    for (int c = 0; c < n; ++c) {
      if (c == a || c == b) continue;
      const auto bc = edge_of.find({std::min(b, c), std::max(b, c)});
      const auto ca = edge_of.find({std::min(a, c), std::max(a, c)});
      if (bc == edge_of.end() || ca == edge_of.end()) continue;
      const Eigen::Quaterniond loop = along(ca->second, c) * along(bc->second, b) * along(e, a);
      if (AngleDeg(loop) < loop_threshold_deg) ++loops[e];
    }
  }
  // Lexicographic weight: loops first, then inliers.
  auto key = [&](int e) { return std::make_pair(loops[e], graph.edges[e].weight); };
  auto worse = [&](const std::pair<int, int>& x, const std::pair<int, int>& y) {
    return key(x.first) < key(y.first) || (key(x.first) == key(y.first) && x.first > y.first);
  };
  std::priority_queue<std::pair<int, int>, std::vector<std::pair<int, int>>, decltype(worse)> queue(worse);
  PerCamera<Eigen::Quaterniond> rot(n);
  rot[reference] = Eigen::Quaterniond::Identity();
  auto push = [&](int cam) {
    for (int e : incident[cam]) queue.push({e, cam});
  };
  push(reference);
  while (!queue.empty()) {
    const auto [e, from] = queue.top();
    queue.pop();
    const int to = graph.edges[e].cam_a == from ? graph.edges[e].cam_b : graph.edges[e].cam_a;
    if (rot[to]) continue;
    rot[to] = (along(e, from) * *rot[from]).normalized();
    push(to);
  }
  return rot;
}

}  // namespace

void RotationAveragingOptions::Check() const {
  auto fail = [](const std::string& why) { throw std::invalid_argument("RotationAveragingOptions: " + why); };
  if (!(loop_threshold_deg > 0)) fail("loop_threshold_deg must be > 0");
  if (!(loss_scale_deg > 0)) fail("loss_scale_deg must be > 0");
  if (!(outlier_threshold_deg > 0)) fail("outlier_threshold_deg must be > 0");
  if (max_iterations < 1) fail("max_iterations must be >= 1");
  if (max_rounds < 1) fail("max_rounds must be >= 1");
}

RotationAveragingResult AverageRotations(const ViewGraph& graph, int reference_camera,
                                         const RotationAveragingOptions& options) {
  options.Check();
  if (reference_camera < 0 || reference_camera >= graph.num_cameras) {
    throw std::invalid_argument("AverageRotations: reference camera " + std::to_string(reference_camera) +
                                " out of range");
  }
  RotationAveragingResult result;
  auto fit = [&](const std::vector<char>& outlier) {
    const std::vector<int> edges = UsableEdges(graph, outlier);
    auto rot = SpanningTreeRotations(graph, edges, reference_camera, options.loop_threshold_deg);
    // The edges inside the component.
    std::vector<int> inside, inliers;
    for (int e : edges) {
      if (rot[graph.edges[e].cam_a] && rot[graph.edges[e].cam_b]) {
        inside.push_back(e);
        inliers.push_back(graph.edges[e].weight);
      }
    }
    auto add = [&](ceres::Problem& problem, ceres::LossFunction* loss, int k, double w, const RotationBlock& block) {
      const ViewGraphEdge& g = graph.edges[inside[k]];
      problem.AddResidualBlock(RelativeRotationCost::Create(g.rotation, w), loss, block(0, g.cam_a), block(0, g.cam_b));
    };
    RefineRotations(inliers, add, {{0, reference_camera}}, options.loss_scale_deg, options.max_iterations, {&rot});
    result.cam_from_rig = rot;
  };
  // Every active edge between solved cameras.
  auto residual_deg = [&](int e) {
    const ViewGraphEdge& g = graph.edges[e];
    const auto& rot = result.cam_from_rig;
    if (!g.active || !rot[g.cam_a] || !rot[g.cam_b]) return std::numeric_limits<double>::quiet_NaN();
    return AngleDeg(g.rotation.conjugate() * *rot[g.cam_b] * rot[g.cam_a]->conjugate());
  };
  DropRounds rounds = FitDroppingOutliers(static_cast<int>(graph.edges.size()), options.max_rounds,
                                          options.outlier_threshold_deg, fit, residual_deg);
  result.outlier = std::move(rounds.outlier);
  result.residual_deg = std::move(rounds.residual_deg);
  result.num_outliers = rounds.num_outliers;
  result.rounds = rounds.rounds;
  // When the rounds ran out with fresh outliers, a camera may hang on rejected edges only.
  UnionFind components(graph.num_cameras);
  for (int e : UsableEdges(graph, result.outlier)) components.Join(graph.edges[e].cam_a, graph.edges[e].cam_b);
  for (int c = 0; c < graph.num_cameras; ++c) {
    if (components.Find(c) != components.Find(reference_camera)) result.cam_from_rig[c].reset();
  }
  return result;
}

}  // namespace rigsim
