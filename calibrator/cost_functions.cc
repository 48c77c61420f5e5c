#include "calibrator/cost_functions.h"

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

}  // namespace rigsim
