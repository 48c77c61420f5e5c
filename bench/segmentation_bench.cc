// Segmentation speed: one photo through a network as `rigsim segment` runs it (pre-processing,
// OpenCV DNN, scores resized back to the photo, class mapping), with OpenCV's baseline code (what
// rigsim runs, for the same labels on every node: calibrator/features/cpu_path.h) and with its own choice
// of the widest vector code the CPU has (what that costs). rigsim ships no network:
//
//   RIGSIM_BENCH_MODEL=deeplabv3.onnx RIGSIM_BENCH_PHOTO=photo.jpg build/bench/rigsim_bench_segment
//   (RIGSIM_BENCH_CLASSES=voc for a 21-class model)
//
// Without them the benchmark says so and times nothing. Reproduce: see BENCHMARKS.md.
#include <cstdlib>
#include <string>

#include <benchmark/benchmark.h>
#include <opencv2/core.hpp>

#include "dataset/image_io.h"
#include "segmentation/segmenter.h"

namespace rigsim {
namespace {

void BM_Segment(benchmark::State& state) {
  const char* model = std::getenv("RIGSIM_BENCH_MODEL");
  const char* photo_path = std::getenv("RIGSIM_BENCH_PHOTO");
  if (model == nullptr || photo_path == nullptr) {
    state.SkipWithError("set RIGSIM_BENCH_MODEL (an .onnx file) and RIGSIM_BENCH_PHOTO");
    return;
  }
  const bool optimized = state.range(0) != 0;
  cv::setUseOptimized(optimized);
  SegmenterOptions options;
  options.model = model;
  if (const char* classes = std::getenv("RIGSIM_BENCH_CLASSES")) options.classes = classes;
  const Segmenter segmenter(options);
  const ImageU8 photo = ReadImageU8(photo_path, 3);
  segmenter.Segment(photo);  // the first run allocates the network's buffers
  const double before = segmenter.inference_seconds();
  for (auto _ : state) benchmark::DoNotOptimize(segmenter.Segment(photo).data.data());
  state.counters["network_s"] = benchmark::Counter((segmenter.inference_seconds() - before) / state.iterations());
  const auto input = segmenter.InputSize(photo.width, photo.height);
  state.SetLabel(std::string(optimized ? "opencv-dispatch " : "baseline ") + std::to_string(photo.width) + "x" +
                 std::to_string(photo.height) + " -> " + std::to_string(input[0]) + "x" + std::to_string(input[1]));
  cv::setUseOptimized(false);
}
BENCHMARK(BM_Segment)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(5);

}  // namespace
}  // namespace rigsim

BENCHMARK_MAIN();
