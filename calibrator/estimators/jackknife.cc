#include "calibrator/estimators/jackknife.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numeric>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <ceres/manifold.h>

#include "geometry/rigid3.h"

namespace rigsim {
namespace {

constexpr int kMinFrames = 3;
// Beyond this many posed frames, runs of consecutive frames are left out together (a delete-a-group
// jackknife): the cost stays that of this many solves of the reduced system.
constexpr int kMaxGroups = 10;

// What a group's rows bring to one point: their share of H_pp, of H_cp and of the point's gradient.
struct PointShare {
  Eigen::Matrix3d h = Eigen::Matrix3d::Zero();
  Eigen::Vector3d g = Eigen::Vector3d::Zero();
  std::map<int, Eigen::RowVector3d> cross;
};

// (m - 1) / m times the scatter of `samples` about their mean.
Eigen::Matrix3d JackknifeCovariance(const std::vector<Eigen::Vector3d>& samples) {
  const double m = static_cast<double>(samples.size());
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (const Eigen::Vector3d& x : samples) mean += x / m;
  Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
  for (const Eigen::Vector3d& x : samples) scatter += (x - mean) * (x - mean).transpose();
  return (m - 1.0) / m * scatter;
}

double WorstAxisStdDeg(const Eigen::Matrix3d& cov) {
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(cov, Eigen::EigenvaluesOnly);
  return RadToDeg(std::sqrt(std::max(eig.eigenvalues().maxCoeff(), 0.0)));
}

// The step -S^+ b over the columns S constrains and `held` does not (NaN elsewhere); directions
// with next to no information take no step.
Eigen::VectorXd SolveOverActiveColumns(const Eigen::MatrixXd& s, const Eigen::VectorXd& b, const std::vector<int>& held) {
  const int dim = static_cast<int>(b.size());
  if (dim == 0) return Eigen::VectorXd();  // nothing adjusted: no step (and no diagonal to scale by)
  const double top_diagonal = s.diagonal().cwiseAbs().maxCoeff();
  std::vector<int> active;
  for (int i = 0; i < dim; ++i) {
    if (s(i, i) > 1e-12 * top_diagonal && std::find(held.begin(), held.end(), i) == held.end()) active.push_back(i);
  }
  Eigen::VectorXd step = Eigen::VectorXd::Constant(dim, std::numeric_limits<double>::quiet_NaN());
  if (active.empty()) return step;
  const int m = static_cast<int>(active.size());
  Eigen::MatrixXd sa(m, m);
  Eigen::VectorXd ba(m);
  for (int i = 0; i < m; ++i) {
    ba[i] = b[active[i]];
    for (int j = 0; j < m; ++j) sa(i, j) = 0.5 * (s(active[i], active[j]) + s(active[j], active[i]));
  }
  // Equilibrated (unit diagonal), so that the cuts below are relative to each column's own scale
  // (PoseCovariance has why); the step is scaled back at the end.
  const Eigen::VectorXd scale = EquilibratingScale(sa);
  sa = scale.asDiagonal() * sa * scale.asDiagonal();
  ba = scale.cwiseProduct(ba);
  // A Cholesky factorisation where S is well conditioned (nearly always: a tenth of the cost of
  // the eigen decomposition), else the pseudo-inverse.
  const Eigen::LDLT<Eigen::MatrixXd> ldlt(sa);
  const Eigen::VectorXd d = ldlt.vectorD();
  Eigen::VectorXd xa;
  if (ldlt.info() == Eigen::Success && d.minCoeff() > 1e-10 * d.maxCoeff()) {
    xa = -ldlt.solve(ba);
  } else {
    const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(sa);
    const double top = std::max(eig.eigenvalues().maxCoeff(), 1e-300);
    Eigen::VectorXd inv = Eigen::VectorXd::Zero(m);
    for (int i = 0; i < m; ++i) {
      if (eig.eigenvalues()[i] > 1e-12 * top) inv[i] = 1.0 / eig.eigenvalues()[i];
    }
    xa = -(eig.eigenvectors() * (inv.asDiagonal() * (eig.eigenvectors().transpose() * ba)));
  }
  for (int i = 0; i < m; ++i) step[active[i]] = scale[i] * xa[i];
  return step;
}

}  // namespace

std::vector<std::vector<int>> JackknifeFrameGroups(const std::vector<int>& posed_frames) {
  const int m = static_cast<int>(posed_frames.size());
  if (m < kMinFrames) return {};
  const int g = std::min(m, kMaxGroups);
  std::vector<std::vector<int>> groups(g);
  for (int i = 0; i < m; ++i) groups[static_cast<size_t>(i) * g / m].push_back(posed_frames[i]);
  return groups;
}

int JackknifePointGroup(int point) { return point % kJackknifePointGroups; }

namespace {

// Splits `ids` (indices into `points`) into `groups` regions, writing each one's group from `first`.
void SplitRegions(const std::vector<Eigen::Vector3d>& points, std::vector<int> ids, int groups, int first,
                  std::vector<int>* out) {
  if (groups <= 1 || ids.size() < 2) {
    for (const int i : ids) (*out)[i] = first;
    return;
  }
  // The axis of the widest spread between the 10th and 90th percentiles: a few far points do not
  // decide it.
  int axis = 0;
  double widest = -1.0;
  for (int a = 0; a < 3; ++a) {
    std::vector<double> v;
    v.reserve(ids.size());
    for (const int i : ids) v.push_back(points[i][a]);
    std::sort(v.begin(), v.end());
    const double spread = v[v.size() * 9 / 10] - v[v.size() / 10];
    if (spread > widest) {
      widest = spread;
      axis = a;
    }
  }
  std::stable_sort(ids.begin(), ids.end(), [&](int x, int y) { return points[x][axis] < points[y][axis]; });
  const int left_groups = groups / 2;
  const size_t cut = ids.size() * static_cast<size_t>(left_groups) / static_cast<size_t>(groups);
  SplitRegions(points, std::vector<int>(ids.begin(), ids.begin() + cut), left_groups, first, out);
  SplitRegions(points, std::vector<int>(ids.begin() + cut, ids.end()), groups - left_groups, first + left_groups, out);
}

}  // namespace

std::vector<int> JackknifeRegionGroups(const std::vector<Eigen::Vector3d>& points) {
  std::vector<int> out(points.size(), 0);
  std::vector<int> ids(points.size());
  std::iota(ids.begin(), ids.end(), 0);
  SplitRegions(points, std::move(ids), kJackknifePointGroups, 0, &out);
  return out;
}

std::vector<Eigen::VectorXd> StepsWithoutGroups(const BundleLinearisation& linearised, const NormalEquations& normal,
                                                const std::vector<int>& block_group, int groups,
                                                const std::vector<std::vector<int>>& held) {
  const Eigen::MatrixXd& reduced = normal.reduced;
  const Eigen::VectorXd& reduced_gradient = normal.reduced_gradient;
  std::vector<std::vector<int>> rows_of(groups);
  for (int r = 0; r < linearised.jacobian.num_rows; ++r) {
    const int g = block_group[linearised.row_block[r]];
    if (g >= 0) rows_of[g].push_back(r);
  }
  std::vector<Eigen::VectorXd> steps;
  JacobianRow row;
  for (int g = 0; g < groups; ++g) {
    // The kept rows' normal equations: the full ones less the group's rows, with each point the
    // group's rows touch eliminated again from its kept rows.
    Eigen::MatrixXd s = reduced;
    Eigen::VectorXd b = reduced_gradient;
    std::map<int, PointShare> touched;
    for (const int r : rows_of[g]) {
      ReadRow(linearised, r, &row);
      const double residual = linearised.residuals[r];
      for (const auto& [col_a, a] : row.pose) {
        for (const auto& [col_b, c] : row.pose) s(col_a, col_b) -= a * c;
        b[col_a] -= a * residual;
      }
      if (row.point < 0) continue;
      PointShare& share = touched[row.point];
      share.h += row.point_entries.transpose() * row.point_entries;
      share.g += row.point_entries.transpose() * residual;
      for (const auto& [col, a] : row.pose) {
        share.cross.try_emplace(col, Eigen::RowVector3d::Zero()).first->second += a * row.point_entries;
      }
    }
    for (const auto& [p, share] : touched) {
      const std::map<int, Eigen::RowVector3d>& full_cross = normal.h_cross[p];
      const Eigen::Matrix3d full_inv = PointPseudoInverse(normal.h_point[p]);
      for (const auto& [col_a, cross_a] : full_cross) {
        const Eigen::RowVector3d weighted = cross_a * full_inv;
        for (const auto& [col_b, cross_b] : full_cross) s(col_a, col_b) += weighted.dot(cross_b);
        b[col_a] += weighted.dot(normal.g_point[p].transpose());
      }
      std::map<int, Eigen::RowVector3d> kept_cross = full_cross;
      for (const auto& [col, c] : share.cross) kept_cross[col] -= c;
      const Eigen::Matrix3d kept_inv = PointPseudoInverse(normal.h_point[p] - share.h);
      const Eigen::Vector3d kept_g = normal.g_point[p] - share.g;
      for (const auto& [col_a, cross_a] : kept_cross) {
        const Eigen::RowVector3d weighted = cross_a * kept_inv;
        for (const auto& [col_b, cross_b] : kept_cross) s(col_a, col_b) -= weighted.dot(cross_b);
        b[col_a] -= weighted.dot(kept_g.transpose());
      }
    }
    steps.push_back(SolveOverActiveColumns(s, b, g < static_cast<int>(held.size()) ? held[g] : std::vector<int>{}));
  }
  return steps;
}

JackknifeSpread LargerSpread(const JackknifeSpread& a, const JackknifeSpread& b) {
  const auto larger = [](const PerCamera<double>& x, const PerCamera<double>& y) {
    PerCamera<double> out(std::max(x.size(), y.size()));
    for (size_t c = 0; c < out.size(); ++c) {
      const std::optional<double> u = c < x.size() ? x[c] : std::nullopt, v = c < y.size() ? y[c] : std::nullopt;
      out[c] = u && v ? std::max(*u, *v) : u ? u : v;
    }
    return out;
  };
  return {std::max(a.groups_left_out, b.groups_left_out), larger(a.rotation_std_deg, b.rotation_std_deg),
          larger(a.direction_std_deg, b.direction_std_deg)};
}

JackknifeSpread CameraSpread(ceres::Problem& problem, const BundleLinearisation& linearised,
                            const std::vector<Eigen::VectorXd>& steps, const std::vector<Eigen::Vector4d>& cq,
                            const std::vector<Eigen::Vector3d>& ct) {
  const int n = static_cast<int>(cq.size());
  JackknifeSpread out;
  out.groups_left_out = static_cast<int>(steps.size());
  out.rotation_std_deg.assign(n, std::nullopt);
  out.direction_std_deg.assign(n, std::nullopt);
  for (int c = 0; c < n; ++c) {
    const auto q_column = linearised.offset.find(cq[c].data());
    const auto t_column = linearised.offset.find(ct[c].data());
    if (q_column == linearised.offset.end() || t_column == linearised.offset.end()) continue;
    const ceres::Manifold* q_manifold = problem.GetManifold(cq[c].data());
    const ceres::Manifold* t_manifold = problem.GetManifold(ct[c].data());
    const int q_size = problem.ParameterBlockTangentSize(cq[c].data());
    const int t_size = problem.ParameterBlockTangentSize(ct[c].data());
    if (!q_manifold || q_size != 3) continue;
    const Eigen::Quaterniond solved_rotation(cq[c].data());
    std::vector<Eigen::Vector3d> turns, centres;
    for (const Eigen::VectorXd& step : steps) {
      const Eigen::VectorXd dq = step.segment(q_column->second, q_size), dt = step.segment(t_column->second, t_size);
      if (!dq.allFinite() || !dt.allFinite()) continue;
      Eigen::Vector4d q;
      Eigen::Vector3d t;
      q_manifold->Plus(cq[c].data(), dq.data(), q.data());
      if (t_manifold) {
        t_manifold->Plus(ct[c].data(), dt.data(), t.data());
      } else {
        t = ct[c] + dt;
      }
      const Eigen::Quaterniond rotation(q.data());
      const Eigen::AngleAxisd turn(rotation * solved_rotation.inverse());
      turns.push_back(turn.angle() * turn.axis());
      centres.push_back(-(rotation.inverse() * t));
    }
    if (turns.size() < 2) continue;
    out.rotation_std_deg[c] = WorstAxisStdDeg(JackknifeCovariance(turns));
    const Eigen::Vector3d solved_centre = -(solved_rotation.inverse() * ct[c]);
    out.direction_std_deg[c] = DirectionStdDeg(solved_centre, JackknifeCovariance(centres));
  }
  return out;
}

}  // namespace rigsim
