#include "calibrator/estimators/time_offset_search.h"
#include "calibrator/model/rig_state.h"

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace rigsim {
namespace {

// Camera 0's accumulated turn at time t: linear between its captures, and beyond the first or
// last one at the neighbouring interval's rate. nullopt where an interval it needs is unknown.
class AccumulatedTurn {
 public:
  AccumulatedTurn(const std::vector<double>& times, const PerFrame<double>& turn)
      : times_(times), turn_(turn), accumulated_(times.size(), 0.0) {
    for (size_t k = 0; k + 1 < times.size(); ++k) accumulated_[k + 1] = accumulated_[k] + turn[k].value_or(0.0);
  }
  std::optional<double> At(double t) const {
    const size_t n = times_.size();
    size_t k = 0;  // the interval [k, k+1] holding t, clamped to the first and last
    while (k + 2 < n && times_[k + 1] <= t) ++k;
    if (!turn_[k]) return std::nullopt;
    const double s = (t - times_[k]) / (times_[k + 1] - times_[k]);
    return accumulated_[k] + s * *turn_[k];
  }

 private:
  const std::vector<double>& times_;
  const PerFrame<double>& turn_;
  std::vector<double> accumulated_;
};

struct Fit {
  double cost = 0.0;
  int intervals = 0;
};

Fit CostAt(double offset, const std::vector<double>& times, const AccumulatedTurn& reference,
           const PerFrame<double>& turn) {
  Fit fit;
  for (size_t k = 0; k + 1 < times.size(); ++k) {
    if (!turn[k]) continue;
    const auto a = reference.At(times[k] + offset), b = reference.At(times[k + 1] + offset);
    if (!a || !b) continue;
    const double r = *turn[k] - (*b - *a);
    fit.cost += r * r;
    ++fit.intervals;
  }
  return fit;
}

}  // namespace

void TimeOffsetSearchOptions::Check() const {
  if (!(max_offset_s > 0) || !std::isfinite(max_offset_s)) throw std::invalid_argument("max_offset_s must be > 0");
  if (!(step_s > 0) || step_s > max_offset_s) throw std::invalid_argument("step_s must be in (0, max_offset_s]");
  if (!(min_cost_rise >= 1)) throw std::invalid_argument("min_cost_rise must be >= 1");
}

std::vector<SearchedOffset> SearchTimeOffsets(const std::vector<double>& frame_times_s,
                                              const std::vector<PerFrame<double>>& turn_rad,
                                              const TimeOffsetSearchOptions& options) {
  options.Check();
  const size_t frames = frame_times_s.size();
  if (frames < 2) throw std::invalid_argument("SearchTimeOffsets: needs at least two frames");
  for (size_t k = 0; k + 1 < frames; ++k) {
    if (!(frame_times_s[k + 1] > frame_times_s[k])) throw std::invalid_argument("SearchTimeOffsets: frame times must increase");
  }
  for (const auto& t : turn_rad) {
    if (t.size() != frames - 1) throw std::invalid_argument("SearchTimeOffsets: one turn per camera and frame interval");
  }
  std::vector<SearchedOffset> out(turn_rad.size());
  if (turn_rad.empty()) return out;
  out[0].determined = true;
  const AccumulatedTurn reference(frame_times_s, turn_rad[0]);
  const double quarter = 0.25 * (frame_times_s.back() - frame_times_s.front()) / static_cast<double>(frames - 1);
  const int steps = static_cast<int>(std::floor(options.max_offset_s / options.step_s));
  for (size_t c = 1; c < turn_rad.size(); ++c) {
    double best_cost = std::numeric_limits<double>::infinity();
    for (int i = -steps; i <= steps; ++i) {
      const double offset = i * options.step_s;
      const Fit fit = CostAt(offset, frame_times_s, reference, turn_rad[c]);
      if (fit.intervals < 2 || fit.cost >= best_cost) continue;
      best_cost = fit.cost;
      out[c].offset_s = offset;
      out[c].intervals = fit.intervals;
    }
    if (!std::isfinite(best_cost)) continue;
    const double floor = options.min_cost_rise * (best_cost + 1e-10);
    const Fit before = CostAt(out[c].offset_s - quarter, frame_times_s, reference, turn_rad[c]);
    const Fit after = CostAt(out[c].offset_s + quarter, frame_times_s, reference, turn_rad[c]);
    out[c].determined = before.intervals >= 2 && after.intervals >= 2 && before.cost >= floor && after.cost >= floor;
  }
  return out;
}

}  // namespace rigsim
