#include "calibrator/matching.h"

#include <algorithm>
#include <chrono>
#include <limits>
#include <map>
#include <stdexcept>
#include <string>

#include <Eigen/Core>

namespace rigsim {
namespace {

using RowMatrixXf = Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

RowMatrixXf GatherRows(const FeatureSet& f, const std::vector<int>& rows) {
  RowMatrixXf m(rows.size(), f.descriptor_size);
  for (size_t r = 0; r < rows.size(); ++r) {
    m.row(r) = Eigen::Map<const Eigen::RowVectorXf>(f.descriptor(rows[r]), f.descriptor_size);
  }
  return m;
}

// Matches the rows `ia` of A against the rows `ib` of B, appending to `out` (global indices).
// Squared distances come from |a|^2 + |b|^2 - 2 a.b with one matrix product per block: the product
// is what brute force costs, and computing it once serves both directions of the mutual check.
void MatchSubset(const FeatureSet& a, const std::vector<int>& ia, const FeatureSet& b, const std::vector<int>& ib,
                 const MatchOptions& options, std::vector<Match>* out, MatchStats* stats) {
  const int na = static_cast<int>(ia.size());
  const int nb = static_cast<int>(ib.size());
  if (na == 0 || nb == 0) return;
  stats->distance_evaluations += int64_t(na) * nb;
  if (nb < 2) return;  // no second-best: the ratio test cannot pass

  const RowMatrixXf db = GatherRows(b, ib);
  const Eigen::VectorXf nb2 = db.rowwise().squaredNorm();
  std::vector<int> best(na, -1);
  std::vector<float> best_d2(na), second_d2(na);
  std::vector<float> col_best_d2(nb, std::numeric_limits<float>::infinity());
  std::vector<int> col_best(nb, -1);

  const float ratio2 = static_cast<float>(options.ratio * options.ratio);
  for (int r0 = 0; r0 < na; r0 += options.block_rows) {
    const int rows = std::min(options.block_rows, na - r0);
    const RowMatrixXf da = GatherRows(a, std::vector<int>(ia.begin() + r0, ia.begin() + r0 + rows));
    const Eigen::VectorXf na2 = da.rowwise().squaredNorm();
    RowMatrixXf d2 = -2.f * (da * db.transpose());
    d2.colwise() += na2;
    d2.rowwise() += nb2.transpose();
    for (int r = 0; r < rows; ++r) {
      float b1 = std::numeric_limits<float>::infinity(), b2 = b1;
      int j1 = -1;
      const float* row = d2.data() + size_t(r) * nb;
      for (int j = 0; j < nb; ++j) {
        const float d = std::max(row[j], 0.f);  // rounding can make it slightly negative
        if (d < b1) {
          b2 = b1;
          b1 = d;
          j1 = j;
        } else if (d < b2) {
          b2 = d;
        }
        // Strict '<' and increasing row order: ties go to the lowest index, whatever the blocking.
        if (d < col_best_d2[j]) {
          col_best_d2[j] = d;
          col_best[j] = r0 + r;
        }
      }
      best[r0 + r] = j1;
      best_d2[r0 + r] = b1;
      second_d2[r0 + r] = b2;
    }
  }
  for (int i = 0; i < na; ++i) {
    if (!(best_d2[i] < ratio2 * second_d2[i])) continue;
    ++stats->ratio_passed;
    if (options.mutual && col_best[best[i]] != i) {
      ++stats->mutual_rejected;
      continue;
    }
    out->push_back({ia[i], ib[best[i]], std::sqrt(best_d2[i])});
  }
}

}  // namespace

void MatchOptions::Check() const {
  auto fail = [](const std::string& why) { throw std::invalid_argument("MatchOptions: " + why); };
  if (!(ratio > 0 && ratio <= 1)) fail("ratio must be in (0, 1]");
  if (block_rows < 1) fail("block_rows must be >= 1");
}

std::vector<Match> MatchFeatures(const FeatureSet& a, const FeatureSet& b, const MatchOptions& options,
                                 MatchStats* stats) {
  options.Check();
  const auto start = std::chrono::steady_clock::now();
  MatchStats local;
  std::vector<Match> matches;
  if (a.size() > 0 && b.size() > 0) {
    if (a.descriptor_size != b.descriptor_size || a.descriptor_size <= 0) {
      throw std::invalid_argument("MatchFeatures: descriptor sizes differ (" + std::to_string(a.descriptor_size) +
                                  " vs " + std::to_string(b.descriptor_size) + ")");
    }
    if (options.gate_by_class) {
      std::map<uint8_t, std::vector<int>> ca, cb;  // ordered: deterministic class order
      for (int i = 0; i < a.size(); ++i) ca[a.keypoints[i].class_id].push_back(i);
      for (int j = 0; j < b.size(); ++j) cb[b.keypoints[j].class_id].push_back(j);
      for (const auto& [cls, ia] : ca) {
        const auto it = cb.find(cls);
        if (it != cb.end()) MatchSubset(a, ia, b, it->second, options, &matches, &local);
      }
      std::sort(matches.begin(), matches.end(), [](const Match& x, const Match& y) { return x.a < y.a; });
    } else {
      std::vector<int> ia(a.size()), ib(b.size());
      for (int i = 0; i < a.size(); ++i) ia[i] = i;
      for (int j = 0; j < b.size(); ++j) ib[j] = j;
      MatchSubset(a, ia, b, ib, options, &matches, &local);
    }
  }
  local.time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (stats != nullptr) *stats = local;
  return matches;
}

}  // namespace rigsim
