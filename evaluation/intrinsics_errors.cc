#include "evaluation/intrinsics_errors.h"

#include <algorithm>
#include <cmath>

namespace rigsim {

double FocalErrorPercent(const std::vector<double>& estimate, const std::vector<double>& truth) {
  return 100.0 * std::max(std::abs(estimate[0] / truth[0] - 1.0), std::abs(estimate[1] / truth[1] - 1.0));
}

double PrincipalPointErrorPx(const std::vector<double>& estimate, const std::vector<double>& truth) {
  return std::hypot(estimate[2] - truth[2], estimate[3] - truth[3]);
}

std::optional<IntrinsicsErrors> ScoreIntrinsics(const std::vector<double>& given, const std::vector<double>& refined,
                                                const Camera& truth) {
  const std::vector<double>& t = truth.params();
  if (refined.size() != t.size() || given.size() != t.size()) return std::nullopt;
  return IntrinsicsErrors{FocalErrorPercent(refined, t), PrincipalPointErrorPx(refined, t), FocalErrorPercent(given, t),
                          PrincipalPointErrorPx(given, t)};
}

}  // namespace rigsim
