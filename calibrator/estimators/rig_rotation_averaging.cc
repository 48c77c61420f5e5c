#include "calibrator/estimators/rig_rotation_averaging.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <stdexcept>
#include <string>

#include <ceres/ceres.h>

#include "calibrator/estimators/cost_functions.h"
#include "calibrator/estimators/robust_rotation_fit.h"
#include "calibrator/model/rig_state.h"
#include "geometry/rigid3.h"

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
  std::vector<int> inside, inliers;
  for (int i = 0; i < static_cast<int>(ms.size()); ++i) {
    if (outlier[i] || !Predicted(ms[i], *q, *r)) continue;
    inside.push_back(i);
    inliers.push_back(ms[i].inliers);
  }
  // Group 0 the cameras' rotations, group 1 the frames'.
  auto add = [&](ceres::Problem& problem, ceres::LossFunction* loss, int k, double w, const RotationBlock& block) {
    const ViewPairRotation& m = ms[inside[k]];
    double* qa = block(0, m.cam_a);
    double* qb = block(0, m.cam_b);
    if (Pooled(m) || m.frame_a == m.frame_b) {
      problem.AddResidualBlock(RelativeRotationCost::Create(m.b_from_a, w), loss, qa, qb);
    } else if (m.cam_a == m.cam_b) {
      problem.AddResidualBlock(ViewMotionRotationCost::Create(m.b_from_a, w), loss, qa, block(1, m.frame_a),
                               block(1, m.frame_b));
    } else {
      problem.AddResidualBlock(ViewPairRotationCost::Create(m.b_from_a, w), loss, qa, block(1, m.frame_a), qb,
                               block(1, m.frame_b));
    }
  };
  RefineRotations(inliers, add, {{0, 0}, {1, 0}}, options.loss_scale_deg, options.max_iterations, {q, r});
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
  auto fit = [&](const std::vector<char>& outlier) {
    Rotations q(num_cameras), r(num_frames);
    q[0] = Eigen::Quaterniond::Identity();
    r[0] = Eigen::Quaterniond::Identity();
    Propagate(ms, outlier, camera_starts, options.loss_scale_deg, &q, &r);
    Refine(ms, outlier, options, &q, &r);
    result.cam_from_rig = q;
    result.rig_from_world = r;
  };
  auto residual_deg = [&](int i) {
    const auto predicted = Predicted(ms[i], result.cam_from_rig, result.rig_from_world);
    if (!predicted) return std::numeric_limits<double>::quiet_NaN();
    return RotationAngleDeg(ms[i].b_from_a.conjugate() * *predicted);
  };
  DropRounds rounds = FitDroppingOutliers(static_cast<int>(ms.size()), options.max_rounds,
                                          options.outlier_threshold_deg, fit, residual_deg);
  result.outlier = std::move(rounds.outlier);
  result.residual_deg = std::move(rounds.residual_deg);
  result.num_outliers = rounds.num_outliers;
  result.rounds = rounds.rounds;
  return result;
}

}  // namespace rigsim
