#include "calibrator/features/row_scan.h"

#include <algorithm>
#include <cstring>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

namespace rigsim {
namespace {

// One row's inputs, the columns' state before it, and what a plain left-to-right scan gives.
struct RowCase {
  std::vector<float> minus_two_dot, nb2, col_best_d2;
  std::vector<int> col_best;
  float na2 = 0.f;
};

struct Scanned {
  RowTop2 top;
  std::vector<float> col_best_d2;
  std::vector<int> col_best;
};

// The scan's definition, one value at a time, as plainly as it can be written.
Scanned PlainScan(const RowCase& c, int i) {
  Scanned s{{-1, std::numeric_limits<float>::infinity(), std::numeric_limits<float>::infinity()},
            c.col_best_d2, c.col_best};
  for (size_t j = 0; j < c.nb2.size(); ++j) {
    const float d = std::max((c.minus_two_dot[j] + c.na2) + c.nb2[j], 0.f);
    if (d < s.col_best_d2[j]) {
      s.col_best_d2[j] = d;
      s.col_best[j] = i;
    }
    if (d < s.top.best) {
      s.top.second = s.top.best;
      s.top.best = d;
      s.top.index = static_cast<int>(j);
    } else if (d < s.top.second) {
      s.top.second = d;
    }
  }
  return s;
}

Scanned PathScan(CpuPath path, const RowCase& c, int i) {
  Scanned s{{}, c.col_best_d2, c.col_best};
  s.top = ScanRow(path, c.minus_two_dot.data(), c.na2, c.nb2.data(), static_cast<int>(c.nb2.size()), i,
                  s.col_best_d2.data(), s.col_best.data());
  return s;
}

bool SameBits(float x, float y) { return std::memcmp(&x, &y, sizeof x) == 0; }

// Distances drawn from few values, so that rows and columns tie often; some products slightly
// larger than the norms' sum, so that the clamp at 0 acts.
RowCase RandomRow(int nb, std::mt19937* rng) {
  std::uniform_int_distribution<int> level(0, 6);
  std::uniform_real_distribution<float> jitter(-1e-3f, 1e-3f);
  RowCase c;
  c.na2 = 1000.f + static_cast<float>(level(*rng));
  for (int j = 0; j < nb; ++j) {
    const float nb2 = 900.f + static_cast<float>(level(*rng));
    const float d = static_cast<float>(level(*rng)) * 50.f + (level(*rng) == 0 ? jitter(*rng) : 0.f);
    c.nb2.push_back(nb2);
    c.minus_two_dot.push_back(d - c.na2 - nb2);
    c.col_best_d2.push_back(level(*rng) == 0 ? std::numeric_limits<float>::infinity() : static_cast<float>(level(*rng)) * 50.f);
    c.col_best.push_back(level(*rng) - 1);
  }
  return c;
}

class RowScanPath : public ::testing::TestWithParam<CpuPath> {};

// Every path, on rows of every length round the vector widths: the plain scan's top two and
// columns, bit for bit.
TEST_P(RowScanPath, GivesThePlainScansResultsBitForBit) {
  const CpuPath path = GetParam();
  if (!CpuSupports(path)) GTEST_SKIP() << "this CPU lacks " << CpuPathName(path);
  std::mt19937 rng(11);
  int rows = 0;
  for (int nb : {2, 3, 7, 8, 9, 15, 16, 17, 31, 32, 33, 47, 64, 100, 1000}) {
    for (int trial = 0; trial < 40; ++trial, ++rows) {
      const RowCase c = RandomRow(nb, &rng);
      const Scanned want = PlainScan(c, rows), got = PathScan(path, c, rows);
      const std::string where = std::string(CpuPathName(path)) + ", nb " + std::to_string(nb) + ", trial " +
                                std::to_string(trial);
      ASSERT_EQ(got.top.index, want.top.index) << where;
      ASSERT_TRUE(SameBits(got.top.best, want.top.best)) << where << ": " << got.top.best << " vs " << want.top.best;
      ASSERT_TRUE(SameBits(got.top.second, want.top.second)) << where;
      for (int j = 0; j < nb; ++j) {
        ASSERT_TRUE(SameBits(got.col_best_d2[j], want.col_best_d2[j])) << where << ", column " << j;
        ASSERT_EQ(got.col_best[j], want.col_best[j]) << where << ", column " << j;
      }
    }
  }
}

// The cases the scan's rules are about, at a position in the last vector and in the tail.
TEST_P(RowScanPath, KeepsTheLowestIndexOfTiesAndCountsARepeatedMinimumAsSecond) {
  const CpuPath path = GetParam();
  if (!CpuSupports(path)) GTEST_SKIP() << "this CPU lacks " << CpuPathName(path);
  for (int nb : {16, 35}) {
    RowCase c;
    c.na2 = 0.f;
    c.nb2.assign(nb, 0.f);
    c.minus_two_dot.assign(nb, 9.f);
    c.col_best_d2.assign(nb, 5.f);
    c.col_best.assign(nb, 3);
    c.minus_two_dot[nb - 2] = 2.f;  // the minimum, twice: the lower index wins, second == best
    c.minus_two_dot[5] = 2.f;
    c.minus_two_dot[1] = -0.5f;     // clamped to 0: below both
    c.minus_two_dot[nb - 1] = -0.25f;
    Scanned got = PathScan(path, c, 4);
    EXPECT_EQ(got.top.index, 1) << nb;
    EXPECT_EQ(got.top.best, 0.f);
    EXPECT_EQ(got.top.second, 0.f);  // the clamp makes index 1's and nb-1's both 0
    EXPECT_EQ(got.col_best[1], 4);
    EXPECT_EQ(got.col_best[5], 4);
    EXPECT_EQ(got.col_best[0], 3);  // 9 is not below 5
    EXPECT_EQ(got.col_best_d2[5], 2.f);
    c.minus_two_dot[1] = 9.f;
    c.minus_two_dot[nb - 1] = 9.f;
    got = PathScan(path, c, 4);
    EXPECT_EQ(got.top.index, 5) << nb;
    EXPECT_EQ(got.top.best, 2.f);
    EXPECT_EQ(got.top.second, 2.f);
  }
}

INSTANTIATE_TEST_SUITE_P(EveryPath, RowScanPath,
                         ::testing::Values(CpuPath::kBaseline, CpuPath::kAvx2, CpuPath::kAvx512Vnni),
                         [](const auto& info) {
                           switch (info.param) {
                             case CpuPath::kBaseline: return std::string("Baseline");
                             case CpuPath::kAvx2: return std::string("Avx2");
                             default: return std::string("Avx512Vnni");
                           }
                         });

}  // namespace
}  // namespace rigsim
