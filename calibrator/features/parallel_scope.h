// How the calibration core runs its stages in parallel: one image, pair or view pair per TBB
// worker. While a ParallelScope exists, TBB uses at most `num_threads` workers (0 = all cores)
// and OpenCV's own threading is off, so that OpenCV inside a worker (SIFT, the essential matrix)
// does not oversubscribe the cores. Scopes nest; the previous settings come back at the end.
#pragma once

#include <memory>

namespace rigsim {

class ParallelScope {
 public:
  explicit ParallelScope(int num_threads);
  ~ParallelScope();
  ParallelScope(const ParallelScope&) = delete;
  ParallelScope& operator=(const ParallelScope&) = delete;

 private:
  struct Limits;
  std::unique_ptr<Limits> limits_;
};

}  // namespace rigsim
