#include "calibrator/cost_functions.h"

#include <ceres/solver.h>

#include "geometry/rigid3.h"

namespace rigsim {

namespace {

// The derivatives of Eigen's q * v, v + 2w (u x v) + 2 u x (u x v) with u = (x, y, z), as written
// (q need not be of unit norm: Ceres's finite steps are not): by v, and by q's coefficients (x, y, z, w).
void RotatedVectorJacobians(const Eigen::Quaterniond& q, const Eigen::Vector3d& v, Eigen::Matrix3d* by_v,
                            Eigen::Matrix<double, 3, 4>* by_q) {
  const Eigen::Vector3d u = q.vec();
  const Eigen::Matrix3d u_cross = CrossProductMatrix(u);
  *by_v = Eigen::Matrix3d::Identity() + 2 * q.w() * u_cross + 2 * u_cross * u_cross;
  by_q->leftCols<3>() = -2 * q.w() * CrossProductMatrix(v) +
                        2 * (u * v.transpose() + u.dot(v) * Eigen::Matrix3d::Identity() - 2 * v * u.transpose());
  by_q->col(3) = 2 * u.cross(v);
}

}  // namespace

bool EvaluateRigReprojectionHeld(const RigReprojectionHeldIntrinsics& held, double const* const* parameters,
                                 double* residuals, double** jacobians) {
  using Jet3 = ceres::Jet<double, 3>;
  const Eigen::Map<const Eigen::Quaterniond> cam_q(parameters[0]), rig_q(parameters[2]);
  const Eigen::Map<const Eigen::Vector3d> cam_t(parameters[1]), rig_t(parameters[3]), point(parameters[4]);
  const Eigen::Vector3d in_rig = rig_q * point + rig_t;
  const Eigen::Vector3d in_cam = cam_q * in_rig + cam_t;
  const Jet3 x[3] = {Jet3(in_cam.x(), 0), Jet3(in_cam.y(), 1), Jet3(in_cam.z(), 2)};
  Jet3 params[RigReprojectionCost::kMaxParams];
  for (int i = 0; i < held.cost.num_params; ++i) params[i] = Jet3(held.intrinsics[i]);
  Jet3 px[2];
  if (!ImgFromCam(held.cost.model, params, x, px)) return false;
  residuals[0] = px[0].a - held.cost.observed.x();
  residuals[1] = px[1].a - held.cost.observed.y();
  if (jacobians == nullptr) return true;
  Eigen::Matrix<double, 2, 3> by_cam;  // d(pixel) / d(point in the camera)
  by_cam.row(0) = px[0].v.transpose();
  by_cam.row(1) = px[1].v.transpose();
  Eigen::Matrix3d cam_by_v, rig_by_v;
  Eigen::Matrix<double, 3, 4> cam_by_q, rig_by_q;
  RotatedVectorJacobians(cam_q, in_rig, &cam_by_v, &cam_by_q);
  RotatedVectorJacobians(rig_q, point, &rig_by_v, &rig_by_q);
  const Eigen::Matrix<double, 2, 3> by_rig = by_cam * cam_by_v;  // d(pixel) / d(point in the rig)
  using Rows4 = Eigen::Map<Eigen::Matrix<double, 2, 4, Eigen::RowMajor>>;
  using Rows3 = Eigen::Map<Eigen::Matrix<double, 2, 3, Eigen::RowMajor>>;
  if (jacobians[0] != nullptr) Rows4{jacobians[0]} = by_cam * cam_by_q;
  if (jacobians[1] != nullptr) Rows3{jacobians[1]} = by_cam;
  if (jacobians[2] != nullptr) Rows4{jacobians[2]} = by_rig * rig_by_q;
  if (jacobians[3] != nullptr) Rows3{jacobians[3]} = by_rig;
  if (jacobians[4] != nullptr) Rows3{jacobians[4]} = by_rig * rig_by_v;
  return true;
}

namespace {

class TimedRigReprojectionCostFunction final : public ceres::SizedCostFunction<2, 4, 3, 4, 3, 4, 3, 2, 3> {
 public:
  explicit TimedRigReprojectionCostFunction(const TimedRigReprojectionCost& cost) : cost_(cost) {}

  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override {
    // Parameters: cam q, cam t, frame a q, t, frame b q, t, timing (offset, readout), point.
    using Jet15 = ceres::Jet<double, 15>;  // frame a (7), frame b (7), the fraction s
    const double* timing = parameters[6];
    const double s = (cost_.frame_time + timing[0] + cost_.row_fraction * timing[1]) / cost_.time_b;
    Eigen::Quaternion<Jet15> q_a, q_b;
    Eigen::Matrix<Jet15, 3, 1> t_a, t_b;
    for (int i = 0; i < 4; ++i) {
      q_a.coeffs()[i] = Jet15(parameters[2][i], i);
      q_b.coeffs()[i] = Jet15(parameters[4][i], 7 + i);
    }
    for (int i = 0; i < 3; ++i) {
      t_a[i] = Jet15(parameters[3][i], 4 + i);
      t_b[i] = Jet15(parameters[5][i], 11 + i);
    }
    Eigen::Quaternion<Jet15> q;
    Eigen::Matrix<Jet15, 3, 1> t;
    InterpolateRigFromWorld<Jet15>(q_a, t_a, q_b, t_b, Jet15(s, 14), &q, &t);
    double rig_q[4], rig_t[3];
    Eigen::Matrix<double, 7, 15> pose_by_inputs;  // rows: q (x, y, z, w), t
    for (int i = 0; i < 4; ++i) {
      rig_q[i] = q.coeffs()[i].a;
      pose_by_inputs.row(i) = q.coeffs()[i].v.transpose();
    }
    for (int i = 0; i < 3; ++i) {
      rig_t[i] = t[i].a;
      pose_by_inputs.row(4 + i) = t[i].v.transpose();
    }
    const double* held_parameters[5] = {parameters[0], parameters[1], rig_q, rig_t, parameters[7]};
    if (jacobians == nullptr) return EvaluateRigReprojectionHeld(cost_.cost, held_parameters, residuals, nullptr);
    Eigen::Matrix<double, 2, 4, Eigen::RowMajor> by_rig_q;
    Eigen::Matrix<double, 2, 3, Eigen::RowMajor> by_rig_t;
    double* held_jacobians[5] = {jacobians[0], jacobians[1], by_rig_q.data(), by_rig_t.data(), jacobians[7]};
    if (!EvaluateRigReprojectionHeld(cost_.cost, held_parameters, residuals, held_jacobians)) return false;
    Eigen::Matrix<double, 2, 7> by_pose;
    by_pose << by_rig_q, by_rig_t;
    const Eigen::Matrix<double, 2, 15> by_inputs = by_pose * pose_by_inputs;
    using Rows4 = Eigen::Map<Eigen::Matrix<double, 2, 4, Eigen::RowMajor>>;
    using Rows3 = Eigen::Map<Eigen::Matrix<double, 2, 3, Eigen::RowMajor>>;
    using Rows2 = Eigen::Map<Eigen::Matrix<double, 2, 2, Eigen::RowMajor>>;
    if (jacobians[2] != nullptr) Rows4{jacobians[2]} = by_inputs.middleCols<4>(0);
    if (jacobians[3] != nullptr) Rows3{jacobians[3]} = by_inputs.middleCols<3>(4);
    if (jacobians[4] != nullptr) Rows4{jacobians[4]} = by_inputs.middleCols<4>(7);
    if (jacobians[5] != nullptr) Rows3{jacobians[5]} = by_inputs.middleCols<3>(11);
    if (jacobians[6] != nullptr) {
      const Eigen::RowVector2d s_by_timing(1.0 / cost_.time_b, cost_.row_fraction / cost_.time_b);
      Rows2{jacobians[6]} = by_inputs.col(14) * s_by_timing;
    }
    return true;
  }

 private:
  TimedRigReprojectionCost cost_;
};

}  // namespace

ceres::CostFunction* TimedRigReprojectionCost::Create(const Camera& camera, const Eigen::Vector2d& observed,
                                                      double frame_time, double time_b, double row_fraction) {
  return new TimedRigReprojectionCostFunction(TimedRigReprojectionCost(camera, observed, frame_time, time_b, row_fraction));
}

template <int kNumIntrinsics>
bool EvaluateRigReprojectionWithIntrinsics(const RigReprojectionCost& cost, double const* const* parameters,
                                           double* residuals, double** jacobians) {
  RigReprojectionCost functor = cost;
  const ceres::AutoDiffCostFunction<RigReprojectionCost, 2, 4, 3, 4, 3, 3, kNumIntrinsics> all(
      &functor, ceres::DO_NOT_TAKE_OWNERSHIP);
  return all.Evaluate(parameters, residuals, jacobians);
}

template bool EvaluateRigReprojectionWithIntrinsics<4>(const RigReprojectionCost&, double const* const*, double*,
                                                       double**);
template bool EvaluateRigReprojectionWithIntrinsics<8>(const RigReprojectionCost&, double const* const*, double*,
                                                       double**);
template bool EvaluateRigReprojectionWithIntrinsics<12>(const RigReprojectionCost&, double const* const*, double*,
                                                        double**);

void SolveRotationProblem(ceres::Problem& problem, int max_iterations) {
  ceres::Solver::Options solver_options;
  solver_options.linear_solver_type = ceres::SPARSE_NORMAL_CHOLESKY;
  solver_options.max_num_iterations = max_iterations;
  solver_options.function_tolerance = 1e-12;
  solver_options.gradient_tolerance = 1e-14;
  solver_options.parameter_tolerance = 1e-12;
  solver_options.num_threads = 1;
  solver_options.logging_type = ceres::SILENT;
  ceres::Solver::Summary summary;
  ceres::Solve(solver_options, &problem, &summary);
}

}  // namespace rigsim
