// The instruction-set paths of the calibrator's matching product (calibrator/byte_product.h),
// chosen at run time so that one binary runs on every x86-64 node. Every path computes the same
// numbers exactly, so results are the same bits whichever runs; the environment variable
// RIGSIM_CPU_PATH forces one (to check that, or to chase a difference between machines).
#pragma once

#include <string_view>
#include <vector>

// The function attributes that compile one function for a path's instructions, whatever the
// flags of the rest of the binary (no -march: the path is chosen at run time).
#if defined(__GNUC__) || defined(__clang__)
#define RIGSIM_TARGET_AVX2 __attribute__((target("avx2")))
#define RIGSIM_TARGET_AVX512 __attribute__((target("avx512f")))
#define RIGSIM_TARGET_VNNI __attribute__((target("avx512f,avx512bw,avx512vnni")))
#endif

namespace rigsim {

enum class CpuPath {
  kBaseline,    // any CPU: plain C++ (x86-64: SSE2)
  kAvx2,        // AVX2 (and POPCNT)
  kAvx512Vnni,  // AVX-512 F, BW and VNNI
};

// "baseline", "avx2", "avx512-vnni": the names RIGSIM_CPU_PATH takes.
std::string_view CpuPathName(CpuPath path);

// Whether this CPU can run the path (kBaseline always).
bool CpuSupports(CpuPath path);

// Every path this CPU can run, baseline first.
std::vector<CpuPath> SupportedCpuPaths();

// The path the kernels use: the fastest this CPU supports, or the one RIGSIM_CPU_PATH names
// ("auto" or unset: the fastest). Read once per process. Throws std::runtime_error naming the
// variable when it names no path, or one this CPU lacks.
CpuPath SelectedCpuPath();

// What SelectedCpuPath decides for the variable's value `forced` (nullptr: unset); for tests.
CpuPath CpuPathFor(const char* forced);

// Turns off OpenCV's own run-time choice of SIMD paths (cv::setUseOptimized(false)) for the
// process, once: its AVX2 paths (SIFT's, image filtering's) detect other keypoints than its
// baseline ones, so without this two machines calibrate the same images differently. Called
// before feature detection, and where the program starts.
void UseOpenCvBaselinePaths();

}  // namespace rigsim
