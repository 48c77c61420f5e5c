#include "pipeline/cpu_paths.h"

#include "calibrator/features/cpu_path.h"

namespace rigsim {

void SelectCpuPaths() {
  SelectedCpuPath();
  UseOpenCvBaselinePaths();  // every command's OpenCV calls (the report's images too) take one path
}

}  // namespace rigsim
