// Helpers shared by the exporters: number formatting and the checks every format needs.
// Internal to rigsim_exports (not included by other modules).
#pragma once

#include <string>
#include <vector>

#include "dataset/dataset.h"
#include "geometry/rig.h"

namespace rigsim::exports_internal {

// Shortest text that reads back to exactly `v` ("%.17g", "-0" written as "0").
std::string Num(double v);
// "[a, b, c]"
std::string NumList(const std::vector<double>& v);

// Throws std::invalid_argument("<format> export: ...") unless every camera has cam_from_rig.
void RequireAllPoses(const Rig& rig, const std::string& format);
// Throws unless every frame has rig_from_world.
void RequireFramePoses(const FramesFile& frames, const std::string& format);

}  // namespace rigsim::exports_internal
