// How long a stage took: the wall time the results report per stage.
#pragma once

#include <chrono>

namespace rigsim {

using StageClock = std::chrono::steady_clock;

// Seconds from `since` until now.
inline double SecondsSince(StageClock::time_point since) {
  return std::chrono::duration<double>(StageClock::now() - since).count();
}

}  // namespace rigsim
