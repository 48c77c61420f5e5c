#include "calibrator/estimators/match_significance.h"

#include <algorithm>
#include <cmath>
#include <random>
#include <limits>
#include <stdexcept>
#include <vector>

namespace rigsim {
namespace {

double Log10Choose(int n, int k) {
  return (std::lgamma(n + 1.0) - std::lgamma(k + 1.0) - std::lgamma(n - k + 1.0)) / std::log(10.0);
}

// log10 P[X >= k] for X ~ Binomial(n, p), summed from the largest term down: the terms fall off
// geometrically beyond the mean, so a few hundred of them hold every significant digit.
double Log10BinomialTail(int n, int k, double p) {
  if (k <= 0) return 0.0;
  if (k > n) return -std::numeric_limits<double>::infinity();
  const double lp = std::log10(p), lq = std::log10(1 - p);
  const int first = std::max(k, static_cast<int>(std::floor(n * p)));
  double top = -std::numeric_limits<double>::infinity();
  std::vector<double> terms;
  for (int i = k; i <= n && i <= first + 400; ++i) {
    terms.push_back(Log10Choose(n, i) + i * lp + (n - i) * lq);
    top = std::max(top, terms.back());
  }
  double sum = 0.0;
  for (double t : terms) sum += std::pow(10.0, t - top);
  return std::min(0.0, top + std::log10(sum));
}

}  // namespace

double Log10FalseAlarms(int n, int k, double p, int sample_size) {
  if (n < sample_size || sample_size < 1) throw std::invalid_argument("Log10FalseAlarms: need n >= sample_size >= 1");
  if (!(p > 0 && p < 1)) throw std::invalid_argument("Log10FalseAlarms: p must be in (0, 1)");
  const double models = Log10Choose(n, sample_size);
  if (k <= sample_size) return models;
  return models + Log10BinomialTail(n - sample_size, k - sample_size, p);
}

double ChanceWithinThreshold(int n, const std::function<double(int, int)>& residual, double threshold, int samples) {
  if (n < 2) return 1.0;
  std::mt19937 rng(12345);  // fixed: the same matches give the same figure
  std::uniform_int_distribution<int> first(0, n - 1), other(0, n - 2);
  int hits = 0;
  for (int s = 0; s < samples; ++s) {
    const int i = first(rng);
    int j = other(rng);
    if (j >= i) ++j;
    hits += residual(i, j) < threshold;
  }
  return (hits + 1.0) / (samples + 1.0);
}

}  // namespace rigsim
