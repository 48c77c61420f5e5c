// A start for the time offsets of an unsynchronised rig's cameras, from their own motions. The
// angle a camera turns between two of its captures is the rig's turn over the same time, whatever
// the camera's mounting (a rotation's angle is unchanged by conjugation); a camera that captures o
// seconds after camera 0 turns, between frames k and k+1, what camera 0's motion turns between
// t_k + o and t_{k+1} + o. The rig's turn is taken to accumulate linearly between camera 0's
// captures, as the renderer and the bundle adjustment move it (geometry/pose_interpolation.h), and
// each offset is the one that explains the camera's turn angles best over a grid.
//
// A rig turning at a constant rate turns the same angle over every interval: the angles then do not
// fix the offset, and the search says so (SearchedOffset::determined) rather than guess.
#pragma once

#include <optional>
#include <vector>
#include "calibrator/model/rig_state.h"

namespace rigsim {

struct TimeOffsetSearchOptions {
  double max_offset_s = 0.2;   // offsets searched in [-max, max]
  double step_s = 0.001;       // grid spacing
  // The best offset is determined when moving it by a quarter of a frame interval either way raises
  // the sum of squared angle residuals by at least this factor over the best's (plus 1e-10 rad^2).
  double min_cost_rise = 4.0;

  // Throws std::invalid_argument naming the first bad field.
  void Check() const;
};

struct SearchedOffset {
  double offset_s = 0.0;  // the grid's best (0 when nothing was compared)
  bool determined = false;
  int intervals = 0;      // frame intervals compared
};

// `frame_times_s`: one per frame, increasing. `turn_rad[c][k]`: the angle camera c turned between
// frames k and k+1 (nullopt where unknown); camera 0's is the reference (offset 0). One result per
// camera; camera 0's is {0, true}. Throws std::invalid_argument on sizes that do not match.
std::vector<SearchedOffset> SearchTimeOffsets(const std::vector<double>& frame_times_s,
                                              const std::vector<PerFrame<double>>& turn_rad,
                                              const TimeOffsetSearchOptions& options = {});

}  // namespace rigsim
