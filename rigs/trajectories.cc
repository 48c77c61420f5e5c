#include "rigs/trajectories.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>

#include "common/param_spec.h"

namespace rigsim {
namespace {

void Fail(const std::string& why) { throw std::invalid_argument("trajectory: " + why); }

std::string FrameName(int k) {
  char name[32];
  std::snprintf(name, sizeof(name), "%06d", k);
  return name;
}

}  // namespace

std::string_view TrajectoryKindName(TrajectoryKind kind) {
  switch (kind) {
    case TrajectoryKind::kStraight: return "straight";
    case TrajectoryKind::kCircle: return "circle";
    case TrajectoryKind::kPolyline: return "polyline";
  }
  throw std::invalid_argument("TrajectoryKindName: invalid kind " + std::to_string(static_cast<int>(kind)));
}

TrajectoryKind TrajectoryKindFromName(std::string_view name) {
  for (TrajectoryKind k : kNamedTrajectoryKinds) {
    if (TrajectoryKindName(k) == name) return k;
  }
  throw std::invalid_argument("unknown trajectory '" + std::string(name) + "': give " +
                              JoinNames(NamesOf(kNamedTrajectoryKinds, TrajectoryKindName)));
}

Eigen::Vector3d HeadingDirection(double heading_deg) {
  const double h = DegToRad(heading_deg);
  return Eigen::Vector3d(std::sin(h), 0.0, -std::cos(h));
}

Rigid3d RigFromWorldAt(const Eigen::Vector3d& position_world, double heading_deg) {
  const double h = DegToRad(heading_deg);
  Eigen::Matrix3d world_from_rig;
  world_from_rig.col(0) = Eigen::Vector3d(std::cos(h), 0.0, std::sin(h));   // right
  world_from_rig.col(1) = Eigen::Vector3d(0.0, -1.0, 0.0);                  // down
  world_from_rig.col(2) = Eigen::Vector3d(std::sin(h), 0.0, -std::cos(h));  // forward
  return Rigid3d(world_from_rig, position_world).Inverse();
}

FramesFile MakeStraightTrajectory(const Eigen::Vector3d& start_world, double heading_deg, int num_frames,
                                  double step_m, double frame_interval_s) {
  TrajectoryOptions o;
  o.start_world = start_world;
  o.heading_deg = heading_deg;
  o.num_frames = num_frames;
  o.step_m = step_m;
  o.frame_interval_s = frame_interval_s;
  return MakeTrajectory(o);
}

FramesFile MakeDemoTrajectory(int num_frames) {
  TrajectoryOptions o;
  o.kind = TrajectoryKind::kCircle;
  o.start_world = Eigen::Vector3d(0.0, 1.6, 4.0);
  o.heading_deg = 0.0;
  o.num_frames = num_frames;
  o.step_m = 2.0;
  o.circle_radius_m = 12.0;
  return MakeTrajectory(o);
}

void TrajectoryOptions::Check() const {
  if (num_frames < 1) Fail("needs at least one frame");
  if (!std::isfinite(step_m)) Fail("step_m must be finite");
  if (!start_world.allFinite()) Fail("start_world must be finite");
  if (kind == TrajectoryKind::kCircle && !(std::abs(circle_radius_m) > 1e-6)) Fail("circle_radius_m must be non-zero");
  if (kind == TrajectoryKind::kPolyline && waypoints.empty()) Fail("a polyline needs at least one waypoint");
}

FramesFile MakeTrajectory(const TrajectoryOptions& o) {
  o.Check();
  FramesFile frames;
  const Eigen::Vector3d f0 = HeadingDirection(o.heading_deg);
  const Eigen::Vector3d right0 = HeadingDirection(o.heading_deg + 90.0);
  for (int k = 0; k < o.num_frames; ++k) {
    const double s = k * o.step_m;  // arc length travelled
    Eigen::Vector3d position = o.start_world;
    double heading = o.heading_deg;
    switch (o.kind) {
      case TrajectoryKind::kStraight:
        position = o.start_world + s * f0;
        break;
      case TrajectoryKind::kCircle: {
        const double r = std::abs(o.circle_radius_m), phi = s / r;
        const Eigen::Vector3d side = o.circle_radius_m > 0 ? Eigen::Vector3d(-right0) : right0;
        position = o.start_world + r * std::sin(phi) * f0 + r * (1.0 - std::cos(phi)) * side;
        heading = o.heading_deg + (o.circle_radius_m > 0 ? -1.0 : 1.0) * RadToDeg(phi);
        break;
      }
      case TrajectoryKind::kPolyline: {
        std::vector<Eigen::Vector3d> pts = {o.start_world};
        pts.insert(pts.end(), o.waypoints.begin(), o.waypoints.end());
        double left = s;
        size_t seg = 0;
        for (; seg + 1 < pts.size(); ++seg) {
          const double len = (pts[seg + 1] - pts[seg]).norm();
          if (left <= len || seg + 2 == pts.size()) break;
          left -= len;
        }
        const Eigen::Vector3d d = pts[seg + 1] - pts[seg];
        const double len = d.norm();
        position = len > 1e-12 ? pts[seg] + std::min(left, len) / len * d : pts[seg];
        if (std::hypot(d.x(), d.z()) > 1e-12) heading = RadToDeg(std::atan2(d.x(), -d.z()));
        break;
      }
    }
    frames.frames.push_back(Frame{FrameName(k), RigFromWorldAt(position, heading), k * o.frame_interval_s});
  }
  return frames;
}

RigTrajectory::RigTrajectory(const FramesFile& frames) {
  for (const Frame& f : frames.frames) {
    if (!f.rig_from_world) Fail("frame '" + f.name + "' has no rig_from_world");
    if (!std::isfinite(f.timestamp_s)) Fail("frame '" + f.name + "' has a timestamp that is not finite");
    keys_.push_back({f.timestamp_s, *f.rig_from_world, f.rig_from_world->rotation.conjugate(),
                     f.rig_from_world->SourceOriginInTarget()});
  }
  if (keys_.empty()) Fail("no frames");
  std::stable_sort(keys_.begin(), keys_.end(), [](const Key& a, const Key& b) { return a.time_s < b.time_s; });
  for (size_t k = 1; k < keys_.size(); ++k) {
    if (keys_[k].time_s == keys_[k - 1].time_s) {
      Fail("two frames share timestamp_s " + std::to_string(keys_[k].time_s) +
           ": the rig's pose between frames (for cameras with a time offset, rolling shutter or exposure) needs "
           "distinct timestamps");
    }
  }
}

Rigid3d RigTrajectory::RigFromWorldAt(double time_s) const {
  if (keys_.size() == 1) return keys_[0].rig_from_world;
  // The segment [k, k + 1] that holds time_s, or the first or last one outside.
  size_t k = size_t(std::upper_bound(keys_.begin(), keys_.end(), time_s,
                                     [](double t, const Key& key) { return t < key.time_s; }) -
                    keys_.begin());
  if (k > 0 && keys_[k - 1].time_s == time_s) return keys_[k - 1].rig_from_world;
  k = std::clamp<size_t>(k, 1, keys_.size() - 1) - 1;
  const Key& a = keys_[k];
  const Key& b = keys_[k + 1];
  const double s = (time_s - a.time_s) / (b.time_s - a.time_s);  // < 0 or > 1 outside: extrapolation
  // Slerp as a fraction of the relative rotation's angle, which extrapolates as well.
  Eigen::Quaterniond delta = a.world_from_rig.conjugate() * b.world_from_rig;
  if (delta.w() < 0) delta.coeffs() *= -1;  // the short way round
  const Eigen::AngleAxisd turn(delta);
  const Eigen::Quaterniond world_from_rig =
      (a.world_from_rig * Eigen::Quaterniond(Eigen::AngleAxisd(s * turn.angle(), turn.axis()))).normalized();
  const Eigen::Vector3d centre = a.centre + s * (b.centre - a.centre);
  return Rigid3d(world_from_rig, centre).Inverse();
}

}  // namespace rigsim
