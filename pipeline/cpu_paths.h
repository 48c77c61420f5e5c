// The CPU code paths a process calibrates with, chosen where the program starts: the calibrator's
// matching kernels (calibrator/features/cpu_path.h; RIGSIM_CPU_PATH forces one) and OpenCV held to
// its baseline paths, so that two machines detect the same keypoints.
#pragma once

namespace rigsim {

// Throws std::runtime_error naming RIGSIM_CPU_PATH when it names no path, or one this CPU lacks:
// called before a command writes anything, so that it stops every command.
void SelectCpuPaths();

}  // namespace rigsim
