#include "calibrator/estimators/cost_functions.h"

#include <algorithm>

#include <ceres/solver.h>
#include <glog/logging.h>

namespace rigsim {

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

void QuietCeresLogs() {
  static const bool quiet = [] {
    FLAGS_minloglevel = std::max(FLAGS_minloglevel, int(google::GLOG_FATAL));
    return true;
  }();
  (void)quiet;
}

void SolveRotationProblem(ceres::Problem& problem, int max_iterations) {
  QuietCeresLogs();
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
