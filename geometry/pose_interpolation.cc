#include "geometry/pose_interpolation.h"

#include <algorithm>

namespace rigsim {

std::vector<TimedPose> SortedByTime(std::vector<TimedPose> path) {
  std::stable_sort(path.begin(), path.end(), [](const TimedPose& a, const TimedPose& b) { return a.time_s < b.time_s; });
  return path;
}

Rigid3d RigFromWorldOnPath(const std::vector<TimedPose>& path, double time_s) {
  if (path.size() == 1) return path[0].rig_from_world;
  // The segment [k, k + 1] that holds time_s, or the first or last one outside.
  size_t k = size_t(std::upper_bound(path.begin(), path.end(), time_s,
                                     [](double t, const TimedPose& key) { return t < key.time_s; }) -
                    path.begin());
  if (k > 0 && path[k - 1].time_s == time_s) return path[k - 1].rig_from_world;
  k = std::clamp<size_t>(k, 1, path.size() - 1) - 1;
  const TimedPose& a = path[k];
  const TimedPose& b = path[k + 1];
  const double s = (time_s - a.time_s) / (b.time_s - a.time_s);  // < 0 or > 1 outside: extrapolation
  Rigid3d out;
  InterpolateRigFromWorld<double>(a.rig_from_world.rotation, a.rig_from_world.translation, b.rig_from_world.rotation,
                                  b.rig_from_world.translation, s, &out.rotation, &out.translation);
  out.rotation.normalize();
  return out;
}

}  // namespace rigsim
