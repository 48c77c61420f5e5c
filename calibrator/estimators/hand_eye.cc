#include "calibrator/estimators/hand_eye.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>

#include <Eigen/Eigenvalues>
#include <Eigen/QR>

#include "common/format.h"

namespace rigsim {
namespace {

// Relative turns past this are left out of the axis fits: near 180 deg a rotation's axis flips
// sign with noise.
constexpr double kMaxAxisTurnDeg = 150.0;

// The turns of two trajectories between the same two frames, as rotation vectors:
// rig(l)_from_rig(k) and cam(l)_from_cam(k) for k < l.
struct TurnPair {
  Eigen::Vector3d rig, cam;
};

std::vector<TurnPair> TurnPairs(const CameraTrajectory& reference, const CameraTrajectory& camera,
                                double min_rotation_deg) {
  std::vector<TurnPair> out;
  const int num_frames = static_cast<int>(reference.size());
  for (int k = 0; k < num_frames; ++k) {
    for (int l = k + 1; l < num_frames; ++l) {
      if (!reference[k] || !reference[l] || !camera[k] || !camera[l]) continue;
      const Eigen::Vector3d rig = RotationVector(reference[l]->rotation * reference[k]->rotation.conjugate());
      const double deg = RadToDeg(rig.norm());
      if (deg < min_rotation_deg || deg > kMaxAxisTurnDeg) continue;
      out.push_back({rig, RotationVector(camera[l]->rotation * camera[k]->rotation.conjugate())});
    }
  }
  return out;
}

// Least-squares (1 / s, o) of the centre equations for a given R_X, with o restricted to the
// columns of `basis` (all of R^3, or the plane across a planar motion's axis).
struct CentreFit {
  double inverse_scale = 0.0;
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();  // o, in the rig
  double relative_rms = std::numeric_limits<double>::infinity();
  int frames = 0;
};

CentreFit FitCentre(const CameraTrajectory& reference, const CameraTrajectory& camera, const Eigen::Matrix3d& r_x,
                    const Eigen::MatrixXd& basis) {
  const int num_frames = static_cast<int>(reference.size());
  const int unknowns = 1 + static_cast<int>(basis.cols());
  std::vector<Eigen::Matrix<double, 3, Eigen::Dynamic>> rows;
  std::vector<Eigen::Vector3d> rhs;
  double path = 0.0;
  for (int k = 1; k < num_frames; ++k) {
    if (!reference[k] || !camera[k]) continue;
    Eigen::Matrix<double, 3, Eigen::Dynamic> a(3, unknowns);
    a.col(0) = r_x.transpose() * camera[k]->SourceOriginInTarget();
    a.rightCols(unknowns - 1) = -(reference[k]->RotationMatrix().transpose() - Eigen::Matrix3d::Identity()) * basis;
    rows.push_back(a);
    rhs.push_back(reference[k]->SourceOriginInTarget());
    path += rhs.back().squaredNorm();
  }
  CentreFit fit;
  fit.frames = static_cast<int>(rows.size());
  if (rows.empty() || !(path > 0)) return fit;
  Eigen::MatrixXd a(3 * rows.size(), unknowns);
  Eigen::VectorXd b(3 * rows.size());
  for (size_t i = 0; i < rows.size(); ++i) {
    a.middleRows(3 * i, 3) = rows[i];
    b.segment<3>(3 * i) = rhs[i];
  }
  const Eigen::VectorXd z = a.colPivHouseholderQr().solve(b);
  fit.inverse_scale = z(0);
  fit.centre = basis * z.tail(unknowns - 1);
  fit.relative_rms = std::sqrt((a * z - b).squaredNorm() / path);
  return fit;
}

// A unit vector across `axis`, and a second across both.
Eigen::Matrix<double, 3, 2> PlaneAcross(const Eigen::Vector3d& axis) {
  const Eigen::Vector3d e1 = axis.unitOrthogonal();
  Eigen::Matrix<double, 3, 2> basis;
  basis << e1, axis.cross(e1).normalized();
  return basis;
}

// R_X of a planar motion: the rig's axis turned onto the camera's, then the turn about the
// camera's axis that lets one mounting explain the camera's centres best (with a positive scale).
Eigen::Matrix3d PlanarRotation(const CameraTrajectory& reference, const CameraTrajectory& camera,
                               const std::vector<TurnPair>& turns, const Eigen::Vector3d& rig_axis,
                               const HandEyeOptions& options) {
  Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
  for (const TurnPair& t : turns) scatter += t.cam * t.cam.transpose();
  Eigen::Vector3d cam_axis = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(scatter).eigenvectors().col(2);
  double sense = 0.0;  // the camera turns the same way round its axis as the rig round its own
  for (const TurnPair& t : turns) sense += t.rig.dot(rig_axis) * t.cam.dot(cam_axis);
  if (sense < 0) cam_axis = -cam_axis;
  const Eigen::Matrix3d onto = Eigen::Quaterniond::FromTwoVectors(rig_axis, cam_axis).toRotationMatrix();
  const Eigen::MatrixXd basis = PlaneAcross(rig_axis);
  auto cost = [&](double phi) {
    const Eigen::Matrix3d r_x = Eigen::AngleAxisd(phi, cam_axis).toRotationMatrix() * onto;
    const CentreFit fit = FitCentre(reference, camera, r_x, basis);
    return fit.inverse_scale > 0 ? fit.relative_rms : std::numeric_limits<double>::infinity();
  };
  const double step = DegToRad(options.planar_search_step_deg);
  double best_phi = 0.0, best = std::numeric_limits<double>::infinity();
  for (double phi = 0.0; phi < 2.0 * std::numbers::pi; phi += step) {
    const double c = cost(phi);
    if (c < best) best = c, best_phi = phi;
  }
  // Golden-section search within one step either side of the best grid point.
  const double golden = 0.5 * (std::sqrt(5.0) - 1.0);
  double lo = best_phi - step, hi = best_phi + step;
  for (int i = 0; i < 60; ++i) {
    const double m1 = hi - golden * (hi - lo), m2 = lo + golden * (hi - lo);
    if (cost(m1) < cost(m2)) hi = m2; else lo = m1;
  }
  const double phi = 0.5 * (lo + hi);
  return Eigen::AngleAxisd(phi, cam_axis).toRotationMatrix() * onto;
}

// RMS (deg) over the frames both trajectories have of the angle between the camera's rotation
// and the rig's moved into the camera by R_X.
double RotationRmsDeg(const CameraTrajectory& reference, const CameraTrajectory& camera, const Eigen::Matrix3d& r_x) {
  double sum = 0.0;
  int n = 0;
  const Eigen::Quaterniond q_x(r_x);
  for (size_t k = 1; k < reference.size(); ++k) {
    if (!reference[k] || !camera[k]) continue;
    const Eigen::Quaterniond predicted = q_x * reference[k]->rotation * q_x.conjugate();
    const double d = RotationDifferenceDeg(camera[k]->rotation, predicted);
    sum += d * d;
    ++n;
  }
  return n > 0 ? std::sqrt(sum / n) : 0.0;
}

// A mounting and how well it explains a camera's trajectory.
struct Mounting {
  Eigen::Matrix3d r_x = Eigen::Matrix3d::Identity();
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();  // o, in the rig
  double inverse_scale = 0.0;                         // 1 / s
  double cost = std::numeric_limits<double>::infinity();  // squared weighted residuals
  int residuals = 0;
};

// The mounting's residuals over the frames both trajectories have: the camera's rotation against
// the rig's moved into it (rad, over rotation_sigma) and the centre equation (over the path's RMS
// distance from frame 0 times centre_sigma).
Eigen::VectorXd MountingResiduals(const CameraTrajectory& reference, const CameraTrajectory& camera,
                                  const Eigen::Matrix3d& r_x, const Eigen::Vector3d& centre, double inverse_scale,
                                  double path_rms, const HandEyeOptions& options) {
  std::vector<double> r;
  const Eigen::Quaterniond q_x(r_x);
  const double w_rot = 1.0 / DegToRad(options.rotation_sigma_deg);
  const double w_centre = 1.0 / (options.centre_sigma * path_rms);
  for (size_t k = 1; k < reference.size(); ++k) {
    if (!reference[k] || !camera[k]) continue;
    const Eigen::Quaterniond predicted = q_x * reference[k]->rotation * q_x.conjugate();
    const Eigen::Vector3d rot = RotationVector(camera[k]->rotation * predicted.conjugate()) * w_rot;
    const Eigen::Vector3d c = (inverse_scale * r_x.transpose() * camera[k]->SourceOriginInTarget() -
                               reference[k]->SourceOriginInTarget() -
                               (reference[k]->RotationMatrix().transpose() - Eigen::Matrix3d::Identity()) * centre) *
                              w_centre;
    for (int i = 0; i < 3; ++i) r.push_back(rot[i]);
    for (int i = 0; i < 3; ++i) r.push_back(c[i]);
  }
  return Eigen::Map<Eigen::VectorXd>(r.data(), static_cast<Eigen::Index>(r.size()));
}

// Levenberg-Marquardt over a left turn of R_X, the centre's coordinates in `basis` and 1 / s, from
// `start`; numerical derivatives (seven unknowns at most).
Mounting RefineMounting(const CameraTrajectory& reference, const CameraTrajectory& camera, const Mounting& start,
                        const Eigen::MatrixXd& basis, double path_rms, const HandEyeOptions& options) {
  const int nb = static_cast<int>(basis.cols());
  const int n = 3 + nb + 1;
  Eigen::VectorXd x0(n);
  x0.setZero();
  x0.segment(3, nb) = basis.transpose() * start.centre;
  x0[n - 1] = start.inverse_scale;
  const Eigen::Matrix3d r0 = start.r_x;
  auto unpack = [&](const Eigen::VectorXd& x, Eigen::Matrix3d* r_x, Eigen::Vector3d* centre, double* inv) {
    const Eigen::Vector3d d = x.head<3>();
    *r_x = (d.norm() > 0 ? Eigen::AngleAxisd(d.norm(), d.normalized()).toRotationMatrix() : Eigen::Matrix3d::Identity()) * r0;
    *centre = basis * x.segment(3, nb);
    *inv = x[n - 1];
  };
  auto residuals = [&](const Eigen::VectorXd& x) {
    Eigen::Matrix3d r_x;
    Eigen::Vector3d centre;
    double inv;
    unpack(x, &r_x, &centre, &inv);
    return MountingResiduals(reference, camera, r_x, centre, inv, path_rms, options);
  };
  auto jacobian = [&](const Eigen::VectorXd& x, const Eigen::VectorXd& r) {
    Eigen::MatrixXd j(r.size(), n);
    for (int i = 0; i < n; ++i) {
      const double h = 1e-7 * std::max(1.0, std::abs(x[i]));
      Eigen::VectorXd xp = x, xm = x;
      xp[i] += h;
      xm[i] -= h;
      j.col(i) = (residuals(xp) - residuals(xm)) / (2 * h);
    }
    return j;
  };
  Eigen::VectorXd x = x0;
  Eigen::VectorXd r = residuals(x);
  double cost = r.squaredNorm(), lambda = 1e-3;
  for (int iter = 0; iter < 100; ++iter) {
    const Eigen::MatrixXd j = jacobian(x, r);
    const Eigen::MatrixXd h = j.transpose() * j;
    const Eigen::VectorXd g = j.transpose() * r;
    bool improved = false;
    while (lambda < 1e12) {
      Eigen::MatrixXd damped = h;
      damped.diagonal() += lambda * h.diagonal().cwiseMax(1e-12);
      const Eigen::VectorXd dx = -damped.ldlt().solve(g);
      const Eigen::VectorXd rn = residuals(x + dx);
      if (rn.allFinite() && rn.squaredNorm() < cost) {
        x += dx;
        r = rn;
        const double previous = cost;
        cost = rn.squaredNorm();
        lambda = std::max(lambda / 10, 1e-12);
        improved = previous - cost > 1e-12 * previous;
        break;
      }
      lambda *= 10;
    }
    if (!improved) break;
  }
  Mounting out;
  unpack(x, &out.r_x, &out.centre, &out.inverse_scale);
  out.cost = cost;
  out.residuals = static_cast<int>(r.size());
  return out;
}

// The covariance of a left turn of the mounting's R_X (rad^2) at the mounting: the inverse of J^T J
// of the residuals over (turn, centre coordinates in `basis`, 1 / s), a pseudo-inverse for the
// directions the trajectories leave open, scaled by the residuals' variance but never below the
// noise the weights assume (exact data would otherwise make every direction certain, the open ones
// included).
Eigen::Matrix3d RotationCovariance(const CameraTrajectory& reference, const CameraTrajectory& camera,
                                   const Mounting& m, const Eigen::MatrixXd& basis, double path_rms,
                                   const HandEyeOptions& options) {
  const int nb = static_cast<int>(basis.cols());
  const int n = 3 + nb + 1;
  Eigen::VectorXd x0(n);
  x0.setZero();
  x0.segment(3, nb) = basis.transpose() * m.centre;
  x0[n - 1] = m.inverse_scale;
  auto residuals = [&](const Eigen::VectorXd& v) {
    const Eigen::Vector3d d = v.head<3>();
    const Eigen::Matrix3d rx =
        (d.norm() > 0 ? Eigen::AngleAxisd(d.norm(), d.normalized()).toRotationMatrix() : Eigen::Matrix3d::Identity()) *
        m.r_x;
    return MountingResiduals(reference, camera, rx, basis * v.segment(3, nb), v[n - 1], path_rms, options);
  };
  const Eigen::VectorXd r0 = residuals(x0);
  Eigen::MatrixXd j(r0.size(), n);
  for (int i = 0; i < n; ++i) {
    const double h = 1e-7 * std::max(1.0, std::abs(x0[i]));
    Eigen::VectorXd xp = x0, xm = x0;
    xp[i] += h;
    xm[i] -= h;
    j.col(i) = (residuals(xp) - residuals(xm)) / (2 * h);
  }
  const int dof = std::max(1, static_cast<int>(r0.size()) - n);
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(j.transpose() * j);
  const double top = std::max(eig.eigenvalues().maxCoeff(), 1e-300);
  Eigen::VectorXd inv(n);
  for (int i = 0; i < n; ++i) inv[i] = 1.0 / std::max(eig.eigenvalues()[i], 1e-14 * top);
  const Eigen::MatrixXd cov = eig.eigenvectors() * inv.asDiagonal() * eig.eigenvectors().transpose();
  return std::max(r0.squaredNorm() / dof, 1.0) * cov.topLeftCorner<3, 3>();
}

HandEyeCamera SolveOneCamera(const CameraTrajectory& reference, const CameraTrajectory& camera,
                             const MotionClass& motion, const HandEyeOptions& options) {
  HandEyeCamera out;
  if (motion.kind == MotionKind::kStraight) {
    out.status = HandEyeStatus::kStraightMotion;
    out.reason = "the rig did not turn (at most " + Fixed(motion.max_rotation_deg, 2) +
                 " deg): on a straight path a camera's own motion does not show its mounting";
    return out;
  }
  const std::vector<TurnPair> turns = TurnPairs(reference, camera, options.min_rotation_deg);
  int shared_frames = 0;
  double path = 0.0;
  for (size_t k = 1; k < reference.size(); ++k) {
    if (!reference[k] || !camera[k]) continue;
    ++shared_frames;
    path += reference[k]->SourceOriginInTarget().squaredNorm();
  }
  if (turns.size() < 2 || shared_frames < 2 || !(path > 0)) {
    out.status = HandEyeStatus::kTooFewFrames;
    out.reason = "tracked at " + std::to_string(shared_frames) +
                 " turned frame(s) besides frame 0 together with the reference camera (need 2)";
    return out;
  }
  const double path_rms = std::sqrt(path / shared_frames);
  const bool planar = motion.kind == MotionKind::kPlanar;
  const Eigen::MatrixXd basis = planar ? Eigen::MatrixXd(PlaneAcross(motion.axis)) : Eigen::MatrixXd(Eigen::Matrix3d::Identity());
  // Starts: the turn about the main axis from the centres, and for a general motion the rotation
  // from the axes; each refined on rotations and centres together, the better kept.
  std::vector<Eigen::Matrix3d> starts{PlanarRotation(reference, camera, turns, motion.axis, options)};
  if (!planar) {
    Eigen::Matrix3d m = Eigen::Matrix3d::Zero();
    for (const TurnPair& t : turns) m += t.cam * t.rig.transpose();
    starts.push_back(NearestRotation(m));
  }
  Mounting best;
  for (const Eigen::Matrix3d& r_x : starts) {
    const CentreFit fit = FitCentre(reference, camera, r_x, basis);
    Mounting start;
    start.r_x = r_x;
    start.centre = fit.centre;
    start.inverse_scale = fit.inverse_scale;
    start.cost = MountingResiduals(reference, camera, r_x, fit.centre, fit.inverse_scale, path_rms, options).squaredNorm();
    // Along a valley the data leave open (a circle), the refinement may walk to a negative scale:
    // the start stands then.
    const Mounting refined = RefineMounting(reference, camera, start, basis, path_rms, options);
    const Mounting& kept = refined.inverse_scale > 0 || !(start.inverse_scale > 0) ? refined : start;
    const bool better = (kept.inverse_scale > 0) != (best.inverse_scale > 0) ? kept.inverse_scale > 0 : kept.cost < best.cost;
    if (better) best = kept;
  }
  out.frames_used = shared_frames;
  out.rotation_rms_deg = RotationRmsDeg(reference, camera, best.r_x);
  out.centre_rms = FitCentre(reference, camera, best.r_x, basis).relative_rms;
  const Eigen::Matrix3d covariance = RotationCovariance(reference, camera, best, basis, path_rms, options);
  out.rotation_std_deg =
      RadToDeg(std::sqrt(std::max(Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(covariance).eigenvalues().maxCoeff(), 0.0)));
  if (out.rotation_rms_deg > options.max_rotation_rms_deg) {
    out.status = HandEyeStatus::kInconsistent;
    out.reason = "its turns differ from the rig's by " + Fixed(out.rotation_rms_deg, 2) +
                 " deg RMS under the best mounting (wrong matches between its frames, or it is not rigidly mounted)";
    return out;
  }
  out.cam_from_rig = Rigid3d(Eigen::Matrix3d(best.r_x), Eigen::Vector3d(-(best.r_x * best.centre)));
  out.scale = best.inverse_scale > 0 ? 1.0 / best.inverse_scale : 0.0;
  if (planar) out.undetermined_axis = motion.axis;
  if (out.rotation_std_deg > options.max_rotation_std_deg) {
    out.status = HandEyeStatus::kRotationUndetermined;
    // The motion's class says why: a planar motion cannot tell a turn about its axis from a shift;
    // a general one turned too little or too alike for the camera's own noise.
    out.reason = "its own motion fixes its rotation in the rig to +-" + Fixed(out.rotation_std_deg, 1) + " deg only: " +
                 (planar ? "the rig turned about one axis at a near-constant rate, under which a turn of the camera "
                           "about that axis and a shift of its centre explain its path about equally well; a path "
                           "that turns both ways, pitches or rolls, or overlap with another camera fixes it"
                         : "the rig's turns (up to " + Fixed(motion.max_rotation_deg, 1) +
                               " deg between frames, about several axes) are too small for the noise of its own "
                               "matches; larger turns, more frames, or overlap with another camera fixes it");
    return out;
  }
  if (!(best.inverse_scale > 0)) {
    out.status = HandEyeStatus::kInconsistent;
    out.reason = "no mounting places its path along the rig's with a positive scale";
    out.cam_from_rig.reset();
    out.undetermined_axis.reset();
    return out;
  }
  out.status = HandEyeStatus::kSolved;
  return out;
}

}  // namespace

const char* MotionKindName(MotionKind kind) {
  switch (kind) {
    case MotionKind::kStraight: return "straight";
    case MotionKind::kPlanar: return "planar";
    case MotionKind::kGeneral: return "general";
  }
  return "?";
}

void HandEyeOptions::Check() const {
  auto fail = [](const std::string& why) { throw std::invalid_argument("HandEyeOptions: " + why); };
  if (!(min_rotation_deg > 0 && min_rotation_deg < kMaxAxisTurnDeg)) fail("min_rotation_deg must be in (0, 150)");
  if (!(max_planar_axis_spread >= 0 && max_planar_axis_spread < 1)) fail("max_planar_axis_spread must be in [0, 1)");
  if (!(planar_search_step_deg > 0 && planar_search_step_deg <= 30)) fail("planar_search_step_deg must be in (0, 30]");
  if (!(max_rotation_rms_deg > 0)) fail("max_rotation_rms_deg must be > 0");
  if (!(max_rotation_std_deg > 0)) fail("max_rotation_std_deg must be > 0");
  if (!(rotation_sigma_deg > 0)) fail("rotation_sigma_deg must be > 0");
  if (!(centre_sigma > 0)) fail("centre_sigma must be > 0");
}

MotionClass ClassifyMotion(const CameraTrajectory& reference, const HandEyeOptions& options) {
  MotionClass out;
  Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
  int turned = 0;
  const int num_frames = static_cast<int>(reference.size());
  for (int k = 0; k < num_frames; ++k) {
    for (int l = k + 1; l < num_frames; ++l) {
      if (!reference[k] || !reference[l]) continue;
      const Eigen::Vector3d w = RotationVector(reference[l]->rotation * reference[k]->rotation.conjugate());
      const double deg = RadToDeg(w.norm());
      out.max_rotation_deg = std::max(out.max_rotation_deg, deg);
      if (deg < options.min_rotation_deg) continue;
      scatter += w * w.transpose();
      ++turned;
    }
  }
  if (turned == 0) return out;
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(scatter);
  const Eigen::Vector3d e = eig.eigenvalues().cwiseMax(0.0);  // ascending
  out.axis = eig.eigenvectors().col(2);
  // A deterministic sign: the largest component positive.
  Eigen::Index largest = 0;
  out.axis.cwiseAbs().maxCoeff(&largest);
  if (out.axis[largest] < 0) out.axis = -out.axis;
  out.axis_spread = e[2] > 0 ? std::sqrt(e[1] / e[2]) : 0.0;
  out.kind = out.axis_spread < options.max_planar_axis_spread ? MotionKind::kPlanar : MotionKind::kGeneral;
  return out;
}

HandEyeResult SolveHandEye(const std::vector<CameraTrajectory>& trajectories, const HandEyeOptions& options) {
  options.Check();
  if (trajectories.empty()) throw std::invalid_argument("SolveHandEye: no trajectory");
  const size_t num_frames = trajectories[0].size();
  for (const CameraTrajectory& t : trajectories) {
    if (t.size() != num_frames) throw std::invalid_argument("SolveHandEye: trajectories differ in length");
  }
  if (num_frames == 0 || !trajectories[0][0]) throw std::invalid_argument("SolveHandEye: the reference has no frame 0");
  HandEyeResult out;
  out.motion = ClassifyMotion(trajectories[0], options);
  HandEyeCamera reference;
  reference.status = HandEyeStatus::kReference;
  reference.cam_from_rig = Rigid3d();
  reference.scale = 1.0;
  out.cameras.push_back(reference);
  for (size_t c = 1; c < trajectories.size(); ++c) {
    out.cameras.push_back(SolveOneCamera(trajectories[0], trajectories[c], out.motion, options));
  }
  return out;
}

}  // namespace rigsim
