#include "calibrator/features/matching.h"

#include <algorithm>
#include <bit>
#include <chrono>
#include <cmath>
#include <cstring>
#include <limits>
#include <map>
#include <optional>
#include <stdexcept>
#include <string>

#include <Eigen/Core>

#include "calibrator/features/byte_product.h"
#include "calibrator/features/cpu_path.h"
#include "calibrator/features/row_scan.h"

namespace rigsim {
namespace {

using RowMatrixXf = Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

// Copies the descriptors `rows[begin, end)` of f into the first rows of `out`.
void GatherRowsInto(const FeatureSet& f, const std::vector<int>& rows, size_t begin, size_t end, RowMatrixXf* out) {
  for (size_t r = begin; r < end; ++r) {
    out->row(r - begin) = Eigen::Map<const Eigen::RowVectorXf>(f.descriptor(rows[r]), f.descriptor_size);
  }
}

// Matches the rows `ia` of A against the rows `ib` of B, appending to `out` (global indices).
// Squared distances come from |a|^2 + |b|^2 - 2 a.b with one matrix product per block: the product
// is what brute force costs, and computing it once serves both directions of the mutual check.
// The block's buffers are allocated once: a fresh 1024 x 12000 block per step costs its page
// faults again every time.
void MatchSubset(const FeatureSet& a, const std::vector<int>& ia, const FeatureSet& b, const std::vector<int>& ib,
                 const MatchOptions& options, std::vector<Match>* out, MatchStats* stats) {
  const int na = static_cast<int>(ia.size());
  const int nb = static_cast<int>(ib.size());
  if (na == 0 || nb == 0) return;
  stats->distance_evaluations += int64_t(na) * nb;
  if (nb < 2) return;  // no second-best: the ratio test cannot pass

  RowMatrixXf db(nb, b.descriptor_size);
  GatherRowsInto(b, ib, 0, ib.size(), &db);
  const Eigen::VectorXf nb2 = db.rowwise().squaredNorm();
  std::vector<int> best(na, -1);
  std::vector<float> best_d2(na), second_d2(na);
  std::vector<float> col_best_d2(nb, std::numeric_limits<float>::infinity());
  std::vector<int> col_best(nb, -1);

  const int block = std::min(options.block_rows, na);
  RowMatrixXf da(block, a.descriptor_size);
  RowMatrixXf d2(block, nb);
  // The integer product gives the float product's numbers exactly (byte_product.h).
  std::optional<ByteProductColumns> byte_columns;
  const CpuPath path = SelectedCpuPath();
  if (ByteProductAvailable(path) && DescriptorsAreBytes(a, ia) && DescriptorsAreBytes(b, ib)) {
    byte_columns.emplace(b, ib, path);
  }
  const float ratio2 = static_cast<float>(options.ratio * options.ratio);
  for (int r0 = 0; r0 < na; r0 += block) {
    const int rows = std::min(block, na - r0);
    GatherRowsInto(a, ia, r0, r0 + rows, &da);
    const Eigen::VectorXf na2 = da.topRows(rows).rowwise().squaredNorm();
    if (byte_columns) {
      byte_columns->MinusTwoDot(a, ia, r0, r0 + rows, d2.data(), nb);
    } else {
      d2.topRows(rows).noalias() = -2.f * (da.topRows(rows) * db.transpose());
    }
    for (int r = 0; r < rows; ++r) {
      const int i = r0 + r;
      const RowTop2 top = ScanRow(path, d2.data() + size_t(r) * nb, na2[r], nb2.data(), nb, i, col_best_d2.data(),
                                  col_best.data());
      best[i] = top.index;
      best_d2[i] = top.best;
      second_d2[i] = top.second;
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

// --- Hamming path ------------------------------------------------------------------------------

// Binary descriptors of `rows`, each zero-padded to `words` 64-bit words (the padding XORs to
// zero, so it adds nothing to a distance).
std::vector<uint64_t> GatherWords(const FeatureSet& f, const std::vector<int>& rows, size_t begin, size_t end,
                                  int words) {
  std::vector<uint64_t> w(size_t(end - begin) * words, 0);
  for (size_t r = begin; r < end; ++r) {
    std::memcpy(w.data() + (r - begin) * words, f.binary_descriptor(rows[r]), size_t(f.descriptor_size));
  }
  return w;
}

template <int kWords>
[[gnu::always_inline]] inline int HammingDistance(const uint64_t* x, const uint64_t* y, int words) {
  int d = 0;
  const int n = kWords > 0 ? kWords : words;
#if defined(__GNUC__) || defined(__clang__)
  // The builtin expands in the caller's target (POPCNT below), where std::popcount might be an
  // out-of-line call compiled for the baseline.
  for (int k = 0; k < n; ++k) d += __builtin_popcountll(x[k] ^ y[k]);
#else
  for (int k = 0; k < n; ++k) d += std::popcount(x[k] ^ y[k]);
#endif
  return d;
}

// Best and second-best per row of the A block and best row per column of B, as in the L2 path.
struct HammingState {
  std::vector<int> best, best_d, second_d;  // per A row
  std::vector<int> col_best, col_best_d;    // per B column
};

// One block of A rows (rows r0 .. r0 + rows) against all of B. B is the outer loop so that it is
// streamed once per block while the block stays in L1. Strict '<' with increasing j gives row ties
// to the lowest B index; with increasing rows, column ties to the lowest A index.
template <int kWords>
[[gnu::always_inline]] inline void HammingBlock(const uint64_t* da, int r0, int rows, const uint64_t* db, int nb,
                                                int words, HammingState* s) {
  for (int j = 0; j < nb; ++j) {
    const uint64_t* y = db + size_t(j) * words;
    int cb = s->col_best_d[j], ci = s->col_best[j];
    for (int r = 0; r < rows; ++r) {
      const int d = HammingDistance<kWords>(da + size_t(r) * words, y, words);
      const int i = r0 + r;
      if (d < s->best_d[i]) {
        s->second_d[i] = s->best_d[i];
        s->best_d[i] = d;
        s->best[i] = j;
      } else if (d < s->second_d[i]) {
        s->second_d[i] = d;
      }
      if (d < cb) {
        cb = d;
        ci = i;
      }
    }
    s->col_best_d[j] = cb;
    s->col_best[j] = ci;
  }
}

// Fixed word counts for ORB (32 bytes) and AKAZE MLDB (61 bytes) let the compiler unroll.
[[gnu::always_inline]] inline void HammingBlockAnyWidth(const uint64_t* da, int r0, int rows, const uint64_t* db,
                                                        int nb, int words, HammingState* s) {
  switch (words) {
    case 4: HammingBlock<4>(da, r0, rows, db, nb, words, s); break;
    case 8: HammingBlock<8>(da, r0, rows, db, nb, words, s); break;
    default: HammingBlock<0>(da, r0, rows, db, nb, words, s); break;
  }
}

// The build targets baseline x86-64, where popcount is a library call; the POPCNT instruction
// (every x86-64 CPU since 2008) makes binary matching several times faster (BENCHMARKS.md), so
// use it when the CPU has it.
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
__attribute__((target("popcnt"))) void HammingBlockPopcnt(const uint64_t* da, int r0, int rows, const uint64_t* db,
                                                          int nb, int words, HammingState* s) {
  HammingBlockAnyWidth(da, r0, rows, db, nb, words, s);
}
bool CpuHasPopcnt() {
  static const bool has = __builtin_cpu_supports("popcnt");
  return has;
}
#endif

void HammingBlockDispatch(const uint64_t* da, int r0, int rows, const uint64_t* db, int nb, int words,
                          HammingState* s) {
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
  if (CpuHasPopcnt()) {
    HammingBlockPopcnt(da, r0, rows, db, nb, words, s);
    return;
  }
#endif
  HammingBlockAnyWidth(da, r0, rows, db, nb, words, s);
}

// Hamming counterpart of MatchSubset: same ratio test, mutual check and tie rules.
void MatchSubsetHamming(const FeatureSet& a, const std::vector<int>& ia, const FeatureSet& b,
                        const std::vector<int>& ib, const MatchOptions& options, std::vector<Match>* out,
                        MatchStats* stats) {
  const int na = static_cast<int>(ia.size());
  const int nb = static_cast<int>(ib.size());
  if (na == 0 || nb == 0) return;
  stats->distance_evaluations += int64_t(na) * nb;
  if (nb < 2) return;  // no second-best: the ratio test cannot pass

  const int words = (a.descriptor_size + 7) / 8;
  const std::vector<uint64_t> db = GatherWords(b, ib, 0, ib.size(), words);
  constexpr int kInf = std::numeric_limits<int>::max();
  HammingState s;
  s.best.assign(na, -1);
  s.best_d.assign(na, kInf);
  s.second_d.assign(na, kInf);
  s.col_best.assign(nb, -1);
  s.col_best_d.assign(nb, kInf);
  // Blocks of A small enough to stay in L1 while B streams past (64 rows of 64 bytes = 4 KB).
  const int block = std::min(options.block_rows, 64);
  for (int r0 = 0; r0 < na; r0 += block) {
    const int rows = std::min(block, na - r0);
    const std::vector<uint64_t> da = GatherWords(a, ia, r0, r0 + rows, words);
    HammingBlockDispatch(da.data(), r0, rows, db.data(), nb, words, &s);
  }
  for (int i = 0; i < na; ++i) {
    if (!(s.best_d[i] < options.ratio * s.second_d[i])) continue;
    ++stats->ratio_passed;
    if (options.mutual && s.col_best[s.best[i]] != i) {
      ++stats->mutual_rejected;
      continue;
    }
    out->push_back({ia[i], ib[s.best[i]], static_cast<float>(s.best_d[i])});
  }
}

void MatchSubsetAnyKind(const FeatureSet& a, const std::vector<int>& ia, const FeatureSet& b,
                        const std::vector<int>& ib, const MatchOptions& options, std::vector<Match>* out,
                        MatchStats* stats) {
  if (a.kind == DescriptorKind::kBinary) {
    MatchSubsetHamming(a, ia, b, ib, options, out, stats);
  } else {
    MatchSubset(a, ia, b, ib, options, out, stats);
  }
}

std::string KindName(DescriptorKind k) { return k == DescriptorKind::kBinary ? "binary" : "float"; }

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
  // Refused even when a set is empty: a mix is a caller's bug, whatever the images gave.
  if (a.kind != b.kind) {
    throw std::invalid_argument("MatchFeatures: cannot match " + KindName(a.kind) + " descriptors against " +
                                KindName(b.kind) + " ones (feature types differ)");
  }
  if (a.size() > 0 && b.size() > 0) {
    const size_t rows_a = a.kind == DescriptorKind::kBinary ? a.binary_descriptors.size() : a.descriptors.size();
    const size_t rows_b = b.kind == DescriptorKind::kBinary ? b.binary_descriptors.size() : b.descriptors.size();
    if (a.descriptor_size > 0 && b.descriptor_size > 0 &&
        (rows_a != size_t(a.size()) * a.descriptor_size || rows_b != size_t(b.size()) * b.descriptor_size)) {
      throw std::invalid_argument("MatchFeatures: descriptor storage does not hold one descriptor per keypoint");
    }
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
        if (it != cb.end()) MatchSubsetAnyKind(a, ia, b, it->second, options, &matches, &local);
      }
      std::sort(matches.begin(), matches.end(), [](const Match& x, const Match& y) { return x.a < y.a; });
    } else {
      std::vector<int> ia(a.size()), ib(b.size());
      for (int i = 0; i < a.size(); ++i) ia[i] = i;
      for (int j = 0; j < b.size(); ++j) ib[j] = j;
      MatchSubsetAnyKind(a, ia, b, ib, options, &matches, &local);
    }
  }
  local.time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (stats != nullptr) *stats = local;
  return matches;
}

}  // namespace rigsim
