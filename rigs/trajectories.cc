#include "rigs/trajectories.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
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
    case TrajectoryKind::kLoop: return "loop";
    case TrajectoryKind::kFigureEight: return "figure-eight";
    case TrajectoryKind::kHandheld: return "handheld";
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
  FramesFile frames = MakeTrajectory(o);
  for (int k = 0; k < num_frames; ++k) frames.frames[k].timestamp_s = 0.2 * k + 0.02 * k * (k - 1);
  return frames;
}

void TrajectoryOptions::Check() const {
  if (num_frames < 1) Fail("needs at least one frame");
  if (!std::isfinite(step_m)) Fail("step_m must be finite");
  if (!(frame_interval_s > 0) || !std::isfinite(frame_interval_s)) Fail("frame_interval_s must be positive");
  if (!start_world.allFinite()) Fail("start_world must be finite");
  const bool curved = kind == TrajectoryKind::kCircle || kind == TrajectoryKind::kLoop ||
                      kind == TrajectoryKind::kFigureEight || kind == TrajectoryKind::kHandheld;
  if (curved && !(std::abs(circle_radius_m) > 1e-6)) Fail("circle_radius_m must be non-zero");
  if (!std::isfinite(circle_radius_m)) Fail("circle_radius_m must be finite");
  if (!(std::abs(tilt_deg) < 90)) Fail("tilt_deg must be between -90 and 90");
  if (kind == TrajectoryKind::kPolyline && waypoints.empty()) Fail("a polyline needs at least one waypoint");
}

namespace {

// Position and heading after `s` metres along a circle of signed radius `radius` (> 0 turning
// left) from `start` heading `heading_deg`.
void AlongCircle(const Eigen::Vector3d& start, double heading_deg, double radius, double s, Eigen::Vector3d* position,
                 double* heading) {
  const Eigen::Vector3d f0 = HeadingDirection(heading_deg);
  const Eigen::Vector3d right0 = HeadingDirection(heading_deg + 90.0);
  const double r = std::abs(radius), phi = s / r;
  const Eigen::Vector3d side = radius > 0 ? Eigen::Vector3d(-right0) : right0;
  *position = start + r * std::sin(phi) * f0 + r * (1.0 - std::cos(phi)) * side;
  *heading = heading_deg + (radius > 0 ? -1.0 : 1.0) * RadToDeg(phi);
}

// Position and heading after `s` metres along the polyline start -> waypoints; it stops at the end.
void AlongPolyline(const TrajectoryOptions& o, double s, Eigen::Vector3d* position, double* heading) {
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
  *position = len > 1e-12 ? pts[seg] + std::min(left, len) / len * d : pts[seg];
  if (std::hypot(d.x(), d.z()) > 1e-12) *heading = RadToDeg(std::atan2(d.x(), -d.z()));
}

// The upright pose tilted in the rig's own frame (the header's convention).
Rigid3d Tilted(const Rigid3d& upright_rig_from_world, double pitch_deg, double roll_deg) {
  const Eigen::Quaterniond tilt = Eigen::AngleAxisd(DegToRad(pitch_deg), Eigen::Vector3d::UnitX()) *
                                  Eigen::AngleAxisd(DegToRad(roll_deg), Eigen::Vector3d::UnitZ());
  const Rigid3d world_from_rig = upright_rig_from_world.Inverse();
  return Rigid3d(world_from_rig.rotation * tilt, world_from_rig.translation).Inverse();
}

}  // namespace

double ClosedPathLength(const TrajectoryOptions& o) {
  const double lap = 2.0 * std::numbers::pi * std::abs(o.circle_radius_m);
  if (o.kind == TrajectoryKind::kLoop) return lap;
  if (o.kind == TrajectoryKind::kFigureEight) return 2.0 * lap;
  return 0.0;
}

double PathStep(const TrajectoryOptions& o) {
  const double length = ClosedPathLength(o);
  return length > 0 ? length / o.num_frames : o.step_m;
}

Rigid3d RigFromWorldAlongPath(const TrajectoryOptions& o, double s) {
  Eigen::Vector3d position = o.start_world;
  double heading = o.heading_deg;
  switch (o.kind) {
    case TrajectoryKind::kStraight:
      position = o.start_world + s * HeadingDirection(o.heading_deg);
      break;
    case TrajectoryKind::kCircle:
    case TrajectoryKind::kHandheld:
      AlongCircle(o.start_world, o.heading_deg, o.circle_radius_m, s, &position, &heading);
      break;
    case TrajectoryKind::kLoop: {
      const double lap = ClosedPathLength(o);
      AlongCircle(o.start_world, o.heading_deg, o.circle_radius_m, s - lap * std::floor(s / lap), &position, &heading);
      break;
    }
    case TrajectoryKind::kFigureEight: {
      // The first lap turns one way, the second the other; both pass the start with its heading.
      const double lap = 0.5 * ClosedPathLength(o), within = s - 2.0 * lap * std::floor(s / (2.0 * lap));
      const bool first = within < lap;
      AlongCircle(o.start_world, o.heading_deg, first ? o.circle_radius_m : -o.circle_radius_m,
                  first ? within : within - lap, &position, &heading);
      break;
    }
    case TrajectoryKind::kPolyline:
      AlongPolyline(o, s, &position, &heading);
      break;
  }
  const Rigid3d upright = RigFromWorldAt(position, heading);
  if (o.kind != TrajectoryKind::kHandheld) return upright;
  return Tilted(upright, o.tilt_deg * std::sin(2.0 * std::numbers::pi * s / kHandheldPitchWavelengthM),
                o.tilt_deg * std::sin(2.0 * std::numbers::pi * s / kHandheldRollWavelengthM));
}

FramesFile MakeTrajectory(const TrajectoryOptions& o) {
  o.Check();
  FramesFile frames;
  const double length = ClosedPathLength(o);
  for (int k = 0; k < o.num_frames; ++k) {
    // Closed paths: k/N of the way round, exactly, so that the frames spread evenly.
    const double s = length > 0 ? length * k / o.num_frames : k * o.step_m;  // distance travelled
    frames.frames.push_back(Frame{FrameName(k), RigFromWorldAlongPath(o, s), k * o.frame_interval_s});
  }
  return frames;
}

std::string DescribePath(const TrajectoryOptions& o) {
  char text[160];
  const std::string name(TrajectoryKindName(o.kind));
  const int n = o.num_frames;
  switch (o.kind) {
    case TrajectoryKind::kStraight:
    case TrajectoryKind::kPolyline:
      std::snprintf(text, sizeof text, "%s path of %d frames (%g m per frame)", name.c_str(), n, o.step_m);
      break;
    case TrajectoryKind::kCircle:
      std::snprintf(text, sizeof text, "circle path of %d frames (radius %g m, %g m per frame)", n, o.circle_radius_m, o.step_m);
      break;
    case TrajectoryKind::kLoop:
    case TrajectoryKind::kFigureEight:
      std::snprintf(text, sizeof text, "%s path of %d frames (radius %g m, %.3g m long)", name.c_str(), n,
                    o.circle_radius_m, ClosedPathLength(o));
      break;
    case TrajectoryKind::kHandheld:
      std::snprintf(text, sizeof text, "handheld path of %d frames (radius %g m, %g m per frame, tilting %g deg)", n,
                    o.circle_radius_m, o.step_m, o.tilt_deg);
      break;
  }
  return text;
}

}  // namespace rigsim
