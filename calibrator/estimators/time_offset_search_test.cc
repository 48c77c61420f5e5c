#include "calibrator/estimators/time_offset_search.h"

#include <cmath>
#include <optional>
#include <stdexcept>
#include <vector>

#include <gtest/gtest.h>

namespace rigsim {
namespace {

// Turn angles of cameras capturing at `offsets` on a rig whose turn rate is `rate(t)` (rad/s),
// with the rig's turn linear between camera 0's captures, as the search models it.
std::vector<std::vector<std::optional<double>>> Turns(const std::vector<double>& times,
                                                      const std::vector<double>& offsets, double (*rate)(double)) {
  // The rig's accumulated turn at camera 0's captures, then linear in between.
  std::vector<double> acc(times.size(), 0.0);
  for (size_t k = 0; k + 1 < times.size(); ++k) acc[k + 1] = acc[k] + rate(times[k]) * (times[k + 1] - times[k]);
  const auto at = [&](double t) {
    size_t k = 0;
    while (k + 2 < times.size() && times[k + 1] <= t) ++k;
    return acc[k] + (t - times[k]) / (times[k + 1] - times[k]) * (acc[k + 1] - acc[k]);
  };
  std::vector<std::vector<std::optional<double>>> out;
  for (double o : offsets) {
    std::vector<std::optional<double>> turns;
    for (size_t k = 0; k + 1 < times.size(); ++k) turns.push_back(at(times[k + 1] + o) - at(times[k] + o));
    out.push_back(turns);
  }
  return out;
}

std::vector<double> Times(int frames) {
  std::vector<double> t;
  for (int k = 0; k < frames; ++k) t.push_back(0.1 * k);
  return t;
}

double Varying(double t) { return 0.3 + 0.25 * std::sin(7.0 * t); }
double Constant(double) { return 0.3; }

TEST(SearchTimeOffsets, FindsOffsetsFromTheTurnAnglesOfAVaryingTurn) {
  const std::vector<double> times = Times(8), offsets = {0.0, 0.030, -0.045};
  const std::vector<SearchedOffset> found = SearchTimeOffsets(times, Turns(times, offsets, Varying));
  ASSERT_EQ(found.size(), 3u);
  EXPECT_TRUE(found[0].determined);
  for (int c = 1; c < 3; ++c) {
    EXPECT_TRUE(found[c].determined) << c;
    EXPECT_NEAR(found[c].offset_s, offsets[c], 0.0015) << c;
  }
}

TEST(SearchTimeOffsets, AConstantTurnRateDoesNotDetermineThem) {
  const std::vector<double> times = Times(8);
  const std::vector<SearchedOffset> found = SearchTimeOffsets(times, Turns(times, {0.0, 0.030}, Constant));
  EXPECT_FALSE(found[1].determined);
}

TEST(SearchTimeOffsets, UnknownTurnsAreSkippedAndSizesChecked) {
  const std::vector<double> times = Times(8);
  auto turns = Turns(times, {0.0, 0.030}, Varying);
  turns[1][2].reset();
  const std::vector<SearchedOffset> found = SearchTimeOffsets(times, turns);
  EXPECT_EQ(found[1].intervals, 6);  // 7 intervals, one unknown
  EXPECT_NEAR(found[1].offset_s, 0.030, 0.0015);
  turns[1].pop_back();
  EXPECT_THROW(SearchTimeOffsets(times, turns), std::invalid_argument);
  EXPECT_THROW(SearchTimeOffsets({0.0, 0.0}, {{0.1}}), std::invalid_argument);
}

}  // namespace
}  // namespace rigsim
