#include "exports/export_common.h"

#include <cstdio>
#include <stdexcept>

namespace rigsim::exports_internal {

std::string Num(double v) {
  if (v == 0.0) return "0";  // also turns -0 into 0
  char buf[40];
  std::snprintf(buf, sizeof(buf), "%.17g", v);
  return buf;
}

std::string NumList(const std::vector<double>& v) {
  std::string s = "[";
  for (size_t i = 0; i < v.size(); ++i) s += (i ? ", " : "") + Num(v[i]);
  return s + "]";
}

void RequireAllPoses(const Rig& rig, const std::string& format) {
  if (rig.cameras.empty()) throw std::invalid_argument(format + " export: the rig has no cameras");
  for (const RigCamera& c : rig.cameras) {
    if (!c.cam_from_rig) {
      throw std::invalid_argument(format + " export: camera '" + c.name +
                                  "' has no cam_from_rig (export a rendered or calibrated rig)");
    }
  }
}

void RequireFramePoses(const FramesFile& frames, const std::string& format) {
  if (frames.frames.empty()) throw std::invalid_argument(format + " export: no frames");
  for (const Frame& f : frames.frames) {
    if (!f.rig_from_world) throw std::invalid_argument(format + " export: frame '" + f.name + "' has no rig_from_world");
  }
}

}  // namespace rigsim::exports_internal
