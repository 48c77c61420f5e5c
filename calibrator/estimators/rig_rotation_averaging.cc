#include "calibrator/estimators/rig_rotation_averaging.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <stdexcept>
#include <string>

#include <ceres/ceres.h>
#include <ceres/manifold.h>

#include "calibrator/estimators/cost_functions.h"
#include "geometry/rigid3.h"
#include "calibrator/model/rig_state.h"

namespace rigsim {
namespace {

using Rotations = PerCamera<Eigen::Quaterniond>;

bool Pooled(const ViewPairRotation& m) { return m.frame_a < 0; }

// The measurement's prediction Q_b R_t' R_t^T Q_a^T from the current rotations; nullopt when one is
// unknown.
std::optional<Eigen::Quaterniond> Predicted(const ViewPairRotation& m, const Rotations& q, const Rotations& r) {
  if (!q[m.cam_a] || !q[m.cam_b]) return std::nullopt;
  if (Pooled(m)) return *q[m.cam_b] * q[m.cam_a]->conjugate();
  if (!r[m.frame_a] || !r[m.frame_b]) return std::nullopt;
  return *q[m.cam_b] * *r[m.frame_b] * r[m.frame_a]->conjugate() * q[m.cam_a]->conjugate();
}

// The unknown rotation a measurement fixes given the others: which (a camera or a frame) and its
// value; nullopt when the measurement has no unknown or more than one, or when the unknown is a
// camera measured only against itself (its own motion does not fix it alone).
struct Solution {
  bool camera = false;
  int index = -1;
  Eigen::Quaterniond value;
};

std::optional<Solution> SolveOne(const ViewPairRotation& m, const Rotations& q, const Rotations& r) {
  const Eigen::Quaterniond& mm = m.b_from_a;
  const auto& qa = q[m.cam_a];
  const auto& qb = q[m.cam_b];
  if (Pooled(m)) {
    if (qa && !qb) return Solution{true, m.cam_b, (mm * *qa).normalized()};
    if (!qa && qb) return Solution{true, m.cam_a, (mm.conjugate() * *qb).normalized()};
    return std::nullopt;
  }
  const auto& ra = r[m.frame_a];
  const auto& rb = r[m.frame_b];
  const int unknown = !qa + !qb * (m.cam_a != m.cam_b) + !ra + !rb * (m.frame_a != m.frame_b);
  if (unknown != 1) return std::nullopt;
  if (!qa || !qb) {
    if (m.cam_a == m.cam_b) return std::nullopt;
    if (!qb) return Solution{true, m.cam_b, (mm * *qa * *ra * rb->conjugate()).normalized()};
    return Solution{true, m.cam_a, (mm.conjugate() * *qb * *rb * ra->conjugate()).normalized()};
  }
  if (!rb) return Solution{false, m.frame_b, (qb->conjugate() * mm * *qa * *ra).normalized()};
  return Solution{false, m.frame_a, (qa->conjugate() * mm.conjugate() * *qb * *rb).normalized()};
}

double RotationAngleDeg(const Eigen::Quaterniond& e) { return RadToDeg(2.0 * std::atan2(e.vec().norm(), std::abs(e.w()))); }

// Propagation from the gauge, by consensus: each step fixes the unknown that the most measurements
// can fix now, to the value the most of them agree on (within the loss scale; then the most
// inliers), so that one wrong measurement, however heavy, does not decide against several right
// ones. When no measurement fixes anything, the first unknown camera with a start of its own gets it.
void Propagate(const std::vector<ViewPairRotation>& ms, const std::vector<char>& outlier, const Rotations& camera_starts,
               double agree_deg, Rotations* q, Rotations* r) {
  for (;;) {
    // Candidates per unknown: key (camera?, index) -> values with their measurement's inliers.
    std::map<std::pair<bool, int>, std::vector<std::pair<Eigen::Quaterniond, int>>> candidates;
    for (size_t i = 0; i < ms.size(); ++i) {
      if (outlier[i]) continue;
      if (const auto s = SolveOne(ms[i], *q, *r)) candidates[{s->camera, s->index}].emplace_back(s->value, ms[i].inliers);
    }
    if (candidates.empty()) {
      bool seeded = false;
      for (size_t c = 0; c < camera_starts.size() && !seeded; ++c) {
        if (!(*q)[c] && camera_starts[c]) {
          (*q)[c] = camera_starts[c]->normalized();
          seeded = true;
        }
      }
      if (!seeded) return;
      continue;
    }
    auto best_unknown = candidates.begin();
    for (auto it = candidates.begin(); it != candidates.end(); ++it) {
      if (it->second.size() > best_unknown->second.size()) best_unknown = it;
    }
    const auto& values = best_unknown->second;
    size_t best = 0;
    std::pair<int, long> best_support{-1, -1};
    for (size_t i = 0; i < values.size(); ++i) {
      std::pair<int, long> support{0, 0};
      for (const auto& [v, inliers] : values) {
        if (RotationAngleDeg(v * values[i].first.conjugate()) <= agree_deg) support.first += 1, support.second += inliers;
      }
      if (support > best_support) best_support = support, best = i;
    }
    const auto [is_camera, index] = best_unknown->first;
    (is_camera ? (*q)[index] : (*r)[index]) = values[best].first;
  }
}

void Refine(const std::vector<ViewPairRotation>& ms, const std::vector<char>& outlier,
            const RigRotationAveragingOptions& options, Rotations* q, Rotations* r) {
  std::vector<int> inside, weights;
  for (int i = 0; i < static_cast<int>(ms.size()); ++i) {
    if (outlier[i] || !Predicted(ms[i], *q, *r)) continue;
    inside.push_back(i);
    weights.push_back(std::max(1, ms[i].inliers));
  }
  if (inside.empty()) return;
  std::vector<int> sorted = weights;
  std::nth_element(sorted.begin(), sorted.begin() + sorted.size() / 2, sorted.end());
  const double median_weight = sorted[sorted.size() / 2];
  std::vector<Eigen::Quaterniond> qv(q->size(), Eigen::Quaterniond::Identity()), rv(r->size(), Eigen::Quaterniond::Identity());
  for (size_t c = 0; c < q->size(); ++c) {
    if ((*q)[c]) qv[c] = *(*q)[c];
  }
  for (size_t k = 0; k < r->size(); ++k) {
    if ((*r)[k]) rv[k] = *(*r)[k];
  }
  ceres::Problem::Options problem_options;
  problem_options.manifold_ownership = ceres::TAKE_OWNERSHIP;
  problem_options.loss_function_ownership = ceres::TAKE_OWNERSHIP;
  ceres::Problem problem(problem_options);
  ceres::LossFunction* loss = new ceres::CauchyLoss(DegToRad(options.loss_scale_deg));
  for (size_t j = 0; j < inside.size(); ++j) {
    const ViewPairRotation& m = ms[inside[j]];
    const double w = std::sqrt(weights[j] / median_weight);
    double* qa = qv[m.cam_a].coeffs().data();
    double* qb = qv[m.cam_b].coeffs().data();
    if (Pooled(m) || m.frame_a == m.frame_b) {
      problem.AddResidualBlock(RelativeRotationCost::Create(m.b_from_a, w), loss, qa, qb);
    } else if (m.cam_a == m.cam_b) {
      problem.AddResidualBlock(ViewMotionRotationCost::Create(m.b_from_a, w), loss, qa, rv[m.frame_a].coeffs().data(),
                               rv[m.frame_b].coeffs().data());
    } else {
      problem.AddResidualBlock(ViewPairRotationCost::Create(m.b_from_a, w), loss, qa, rv[m.frame_a].coeffs().data(), qb,
                               rv[m.frame_b].coeffs().data());
    }
  }
  auto set_up = [&](Eigen::Quaterniond& x, bool gauge) {
    double* block = x.coeffs().data();
    if (!problem.HasParameterBlock(block)) return;
    if (gauge) {
      problem.SetParameterBlockConstant(block);
    } else {
      problem.SetManifold(block, new ceres::EigenQuaternionManifold);
    }
  };
  for (size_t c = 0; c < qv.size(); ++c) set_up(qv[c], c == 0);
  for (size_t k = 0; k < rv.size(); ++k) set_up(rv[k], k == 0);
  SolveRotationProblem(problem, options.max_iterations);
  for (size_t c = 0; c < q->size(); ++c) {
    if ((*q)[c]) (*q)[c] = qv[c].normalized();
  }
  for (size_t k = 0; k < r->size(); ++k) {
    if ((*r)[k]) (*r)[k] = rv[k].normalized();
  }
}

}  // namespace

void RigRotationAveragingOptions::Check() const {
  auto fail = [](const std::string& why) { throw std::invalid_argument("RigRotationAveragingOptions: " + why); };
  if (!(loss_scale_deg > 0)) fail("loss_scale_deg must be > 0");
  if (!(outlier_threshold_deg > 0)) fail("outlier_threshold_deg must be > 0");
  if (max_iterations < 1) fail("max_iterations must be >= 1");
  if (max_rounds < 1) fail("max_rounds must be >= 1");
}

RigRotationAveragingResult AverageRigRotations(int num_cameras, int num_frames,
                                               const std::vector<ViewPairRotation>& ms,
                                               const PerCamera<Eigen::Quaterniond>& camera_starts,
                                               const RigRotationAveragingOptions& options) {
  options.Check();
  if (num_cameras < 1 || num_frames < 1) throw std::invalid_argument("AverageRigRotations: no camera or no frame");
  if (!camera_starts.empty() && static_cast<int>(camera_starts.size()) != num_cameras) {
    throw std::invalid_argument("AverageRigRotations: camera_starts needs one entry per camera");
  }
  for (const ViewPairRotation& m : ms) {
    const bool cams = m.cam_a >= 0 && m.cam_a < num_cameras && m.cam_b >= 0 && m.cam_b < num_cameras;
    const bool pooled = m.frame_a == -1 && m.frame_b == -1;
    const bool frames = pooled || (m.frame_a >= 0 && m.frame_a < num_frames && m.frame_b >= 0 && m.frame_b < num_frames);
    if (!cams || !frames) throw std::invalid_argument("AverageRigRotations: a measurement names a camera or frame out of range");
    if (m.cam_a == m.cam_b && (pooled || m.frame_a == m.frame_b)) {
      throw std::invalid_argument("AverageRigRotations: a measurement of a view against itself");
    }
  }
  RigRotationAveragingResult result;
  result.outlier.assign(ms.size(), 0);
  result.residual_deg.assign(ms.size(), std::numeric_limits<double>::quiet_NaN());
  for (int round = 0; round < options.max_rounds; ++round) {
    result.rounds = round + 1;
    Rotations q(num_cameras), r(num_frames);
    q[0] = Eigen::Quaterniond::Identity();
    r[0] = Eigen::Quaterniond::Identity();
    Propagate(ms, result.outlier, camera_starts, options.loss_scale_deg, &q, &r);
    Refine(ms, result.outlier, options, &q, &r);
    result.cam_from_rig = q;
    result.rig_from_world = r;
    int fresh = 0;
    for (size_t i = 0; i < ms.size(); ++i) {
      const auto predicted = Predicted(ms[i], q, r);
      result.residual_deg[i] =
          predicted ? RotationAngleDeg(ms[i].b_from_a.conjugate() * *predicted) : std::numeric_limits<double>::quiet_NaN();
      if (!result.outlier[i] && predicted && result.residual_deg[i] > options.outlier_threshold_deg) {
        result.outlier[i] = 1;
        ++fresh;
      }
    }
    result.num_outliers += fresh;
    if (fresh == 0) break;
  }
  return result;
}

}  // namespace rigsim
