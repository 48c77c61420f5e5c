#include "calibrator/features/parallel_scope.h"

#include <opencv2/core.hpp>
#include <tbb/global_control.h>

namespace rigsim {

struct ParallelScope::Limits {
  std::unique_ptr<tbb::global_control> tbb_workers;
  int opencv_threads = 0;  // OpenCV's setting before the scope
};

ParallelScope::ParallelScope(int num_threads) : limits_(std::make_unique<Limits>()) {
  if (num_threads > 0) {
    limits_->tbb_workers = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism,
                                                                 static_cast<size_t>(num_threads));
  }
  limits_->opencv_threads = cv::getNumThreads();
  cv::setNumThreads(1);
}

ParallelScope::~ParallelScope() { cv::setNumThreads(limits_->opencv_threads); }

}  // namespace rigsim
