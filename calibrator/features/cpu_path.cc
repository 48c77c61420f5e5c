#include "calibrator/features/cpu_path.h"

#include <cstdlib>
#include <mutex>
#include <stdexcept>
#include <string>

#include <opencv2/core/utility.hpp>

namespace rigsim {

constexpr CpuPath kAllCpuPaths[] = {CpuPath::kBaseline, CpuPath::kAvx2, CpuPath::kAvx512Vnni};

std::string_view CpuPathName(CpuPath path) {
  switch (path) {
    case CpuPath::kBaseline: return "baseline";
    case CpuPath::kAvx2: return "avx2";
    case CpuPath::kAvx512Vnni: return "avx512-vnni";
  }
  return "?";
}

bool CpuSupports(CpuPath path) {
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
  switch (path) {
    case CpuPath::kBaseline: return true;
    case CpuPath::kAvx2: return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("popcnt");
    case CpuPath::kAvx512Vnni:
      return __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512bw") &&
             __builtin_cpu_supports("avx512vnni");
  }
  return false;
#else
  return path == CpuPath::kBaseline;
#endif
}

std::vector<CpuPath> SupportedCpuPaths() {
  std::vector<CpuPath> paths;
  for (CpuPath p : kAllCpuPaths) {
    if (CpuSupports(p)) paths.push_back(p);
  }
  return paths;
}

CpuPath CpuPathFor(const char* forced) {
  const std::vector<CpuPath> supported = SupportedCpuPaths();
  const std::string value = forced ? forced : "";
  if (value.empty() || value == "auto") return supported.back();
  std::string names, have;
  for (CpuPath p : kAllCpuPaths) {
    names += (names.empty() ? "" : ", ") + std::string(CpuPathName(p));
    if (CpuSupports(p)) have += (have.empty() ? "" : ", ") + std::string(CpuPathName(p));
  }
  for (CpuPath p : kAllCpuPaths) {
    if (value != CpuPathName(p)) continue;
    if (!CpuSupports(p)) {
      throw std::runtime_error("RIGSIM_CPU_PATH=" + value + ": this CPU cannot run that path (it can run: " + have +
                               ")");
    }
    return p;
  }
  throw std::runtime_error("RIGSIM_CPU_PATH=" + value + ": not a CPU path (give auto, " + names + ")");
}

CpuPath SelectedCpuPath() {
  static const CpuPath path = CpuPathFor(std::getenv("RIGSIM_CPU_PATH"));
  return path;
}

void UseOpenCvBaselinePaths() {
  static std::once_flag once;
  std::call_once(once, [] { cv::setUseOptimized(false); });
}

}  // namespace rigsim
