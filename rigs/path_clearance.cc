#include "rigs/path_clearance.h"

#include <cmath>
#include <utility>
#include <vector>

namespace rigsim {

bool Boxed(const GridCaster& caster, const Eigen::Vector3d& position) {
  if (caster.Cast(position, Eigen::Vector3d(0, 1, 0), 0.5)) return true;
  for (int k = 0; k < 8; ++k) {
    const double a = k * 0.7853981633974483;  // 45 deg steps
    if (caster.Cast(position, Eigen::Vector3d(std::sin(a), 0, std::cos(a)), 0.6)) return true;
  }
  return false;
}

bool SegmentHits(const GridCaster& caster, const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  const double length = (b - a).norm();
  return length > 1e-9 && caster.Cast(a, (b - a) / length, length).has_value();
}

bool PathIsClear(const GridCaster& caster, const Rig& rig, const FramesFile& frames, double height_m) {
  constexpr double kGroundTolerance = 0.5;
  std::vector<Eigen::Vector3d> previous;  // centre, then each camera's, at the previous frame
  for (const Frame& frame : frames.frames) {
    const Rigid3d world_from_rig = frame.rig_from_world->Inverse();
    std::vector<Eigen::Vector3d> centres = {world_from_rig.translation};
    for (const RigCamera& rc : rig.cameras) centres.push_back(world_from_rig * rc.cam_from_rig->Inverse().translation);
    const auto ground = caster.Cast(centres[0], Eigen::Vector3d(0, -1, 0), height_m + kGroundTolerance);
    if (!ground || ground->t < height_m - kGroundTolerance || Boxed(caster, centres[0])) return false;
    for (size_t i = 1; i < centres.size(); ++i) {
      if (SegmentHits(caster, centres[0], centres[i])) return false;
    }
    for (size_t i = 0; i < previous.size(); ++i) {
      if (SegmentHits(caster, previous[i], centres[i])) return false;
    }
    previous = std::move(centres);
  }
  return true;
}

}  // namespace rigsim
