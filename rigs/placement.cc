#include "rigs/placement.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "rigs/grid_caster.h"
#include "rigs/path_clearance.h"
#include "rigs/rng.h"
#include "rigs/road_placement.h"
#include "rigs/trajectories.h"

namespace rigsim {
namespace {

void FailPlacing(const std::string& what, const std::string& why) { throw std::invalid_argument(what + ": " + why); }

// Fraction of a's surface samples (rays that hit the scene) that b sees unoccluded.
double PredictedOverlapOneWay(const GridCaster& caster, const RigCamera& a, const RigCamera& b, const Rigid3d& rig_from_world) {
  const Rigid3d world_from_a = (*a.cam_from_rig * rig_from_world).Inverse();
  const Rigid3d b_from_world = *b.cam_from_rig * rig_from_world;
  const Eigen::Vector3d centre_b = b_from_world.Inverse().translation;
  const int nx = 48, ny = std::max(8, int(std::lround(48.0 * a.camera.height() / a.camera.width())));
  int surface = 0, seen = 0;
  for (int j = 0; j < ny; ++j) {
    for (int i = 0; i < nx; ++i) {
      const Eigen::Vector2d px((i + 0.5) * a.camera.width() / nx - 0.5, (j + 0.5) * a.camera.height() / ny - 0.5);
      const std::optional<Eigen::Vector3d> ray = a.camera.CamFromImg(px);
      if (!ray) continue;
      const Eigen::Vector3d dir = world_from_a.rotation * *ray;
      const auto hit = caster.Cast(world_from_a.translation, dir);
      if (!hit) continue;  // sky: not part of the ground-truth overlap
      ++surface;
      const Eigen::Vector3d x = world_from_a.translation + hit->t * dir;
      const auto pb = b.camera.ImgFromCam(b_from_world * x);
      if (!pb || !b.camera.IsInImage(*pb)) continue;
      const double dist = (x - centre_b).norm();
      const auto occluder = caster.Cast(centre_b, (x - centre_b) / dist, dist);
      if (!occluder || occluder->t >= dist - std::max(0.05, 0.02 * dist)) ++seen;
    }
  }
  return surface ? double(seen) / surface : 0.0;
}

// The smaller of the two directions: the figure overlap.json's readers (render, calibrate) report.
double PredictedOverlapWith(const GridCaster& caster, const Rig& rig, int a, int b, const Rigid3d& rig_from_world) {
  return std::min(PredictedOverlapOneWay(caster, rig.cameras[a], rig.cameras[b], rig_from_world),
                  PredictedOverlapOneWay(caster, rig.cameras[b], rig.cameras[a], rig_from_world));
}

}  // namespace

double PredictedOverlap(const Scene& scene, const Rig& rig, int a, int b, const Rigid3d& rig_from_world) {
  if (a < 0 || b < 0 || a >= int(rig.cameras.size()) || b >= int(rig.cameras.size()) || !rig.HasAllPoses()) {
    FailPlacing("predicted overlap", "camera index out of range or camera without cam_from_rig");
  }
  return PredictedOverlapWith(GridCaster(scene), rig, a, b, rig_from_world);
}

Eigen::MatrixXd PredictedOverlaps(const Scene& scene, const Rig& rig, const Rigid3d& rig_from_world) {
  if (!rig.HasAllPoses()) FailPlacing("predicted overlap", "every camera needs cam_from_rig");
  const GridCaster caster(scene);
  const int n = int(rig.cameras.size());
  Eigen::MatrixXd overlap = Eigen::MatrixXd::Zero(n, n);
  for (int a = 0; a < n; ++a) {
    for (int b = a + 1; b < n; ++b) overlap(a, b) = overlap(b, a) = PredictedOverlapWith(caster, rig, a, b, rig_from_world);
  }
  return overlap;
}

Rig MakeRingRigInScene(const RingRigOptions& options, const Scene& scene, const Rigid3d& rig_from_world) {
  options.Check();
  if (!(options.target_overlap > 0)) FailPlacing("ring rig", "MakeRingRigInScene needs target_overlap in (0, 1)");
  Rig rig = MakeRingRig(options);  // the angular solution: intrinsics, and cam0's yaw
  const GridCaster caster(scene);
  auto yaw_of = [&](int i) {
    const Eigen::Vector3d axis = rig.cameras[i].cam_from_rig->Inverse().rotation * Eigen::Vector3d::UnitZ();
    return RadToDeg(std::atan2(axis.x(), axis.z()));
  };
  auto place = [&](int i, double yaw_deg) { rig.cameras[i].cam_from_rig = RingCamFromRig(options.radius_m, yaw_deg); };
  for (int i = 1; i < options.num_cameras; ++i) {
    const double base = yaw_of(i - 1);
    double lo = base, hi = base + std::min(179.0, 1.5 * options.hfov_deg);
    for (int it = 0; it < 14; ++it) {
      const double mid = 0.5 * (lo + hi);
      place(i, mid);
      (PredictedOverlapWith(caster, rig, i - 1, i, rig_from_world) > options.target_overlap ? lo : hi) = mid;
    }
    place(i, 0.5 * (lo + hi));
  }
  return rig;
}

std::string_view PlacementModeName(PlacementMode mode) {
  switch (mode) {
    case PlacementMode::kStructure: return "structure";
    case PlacementMode::kRoad: return "road";
  }
  throw std::invalid_argument("PlacementModeName: invalid mode " + std::to_string(static_cast<int>(mode)));
}

PlacementMode PlacementModeFromName(std::string_view name) {
  for (PlacementMode m : kAllPlacementModes) {
    if (PlacementModeName(m) == name) return m;
  }
  throw std::invalid_argument("unknown placement '" + std::string(name) + "': give structure or road");
}

void PlacementOptions::Check() const {
  const std::string w = "rig placement";
  if (!(height_m > 0)) FailPlacing(w, "height_m must be > 0");
  if (!(min_clearance_m >= 0)) FailPlacing(w, "min_clearance_m must be >= 0");
  if (!(travel_m >= 0)) FailPlacing(w, "travel_m must be >= 0");
  if (!(max_range_m > min_clearance_m)) FailPlacing(w, "max_range_m must exceed min_clearance_m");
  if (num_candidates < 1 || num_headings < 1) FailPlacing(w, "num_candidates and num_headings must be >= 1");
  if (!(half_width_m >= 0)) FailPlacing(w, "half_width_m must be >= 0");
  if (!(two_lane_width_m > 0)) FailPlacing(w, "two_lane_width_m must be > 0");
}

std::optional<RigPlacement> PlaceRig(const Scene& scene, const Rig& rig, const PlacementOptions& o,
                                     const TrajectoryOptions* path) {
  o.Check();
  if (!rig.HasAllPoses()) FailPlacing("rig placement", "every camera needs cam_from_rig");
  const GridCaster caster(scene);
  if (caster.empty()) return std::nullopt;
  if (o.mode == PlacementMode::kRoad) return PlaceRigOnRoad(scene, caster, rig, o, path);
  const Eigen::Vector3d lo = caster.lo(), hi = caster.hi();
  // Probe rays per camera, in the camera frame: the optical axis and a small cross around it
  // ("central rays", which must be clear), plus a wider fan that scores structure.
  std::vector<Eigen::Vector3d> central, fan;
  for (double a : {0.0, -0.15, 0.15}) central.push_back(Eigen::Vector3d(std::sin(a), 0, std::cos(a)));
  central.push_back(Eigen::Vector3d(0, -0.1, 1).normalized());
  for (int i = -3; i <= 3; ++i) {
    for (int j = -1; j <= 1; ++j) fan.push_back(Eigen::Vector3d(0.25 * i, 0.2 * j, 1.0).normalized());
  }
  const double ground_tolerance = 0.5;  // the surface under the rig must be within this of the lowest level
  Rng rng(o.seed);
  std::optional<RigPlacement> best;
  const double margin_x = 0.05 * (hi.x() - lo.x()), margin_z = 0.05 * (hi.z() - lo.z());
  for (int c = 0; c < o.num_candidates; ++c) {
    const double x = rng.Uniform(lo.x() + margin_x, hi.x() - margin_x);
    const double z = rng.Uniform(lo.z() + margin_z, hi.z() - margin_z);
    // The ground: the first surface seen from above must be at the scene's lowest level.
    const auto down = caster.Cast(Eigen::Vector3d(x, hi.y() + 1.0, z), Eigen::Vector3d(0, -1, 0));
    if (!down) continue;
    const double ground_y = hi.y() + 1.0 - down->t;
    if (ground_y > lo.y() + ground_tolerance) continue;
    const Eigen::Vector3d position(x, ground_y + o.height_m, z);
    if (Boxed(caster, position)) continue;  // not inside anything
    for (int h = 0; h < o.num_headings; ++h) {
      const double heading = 360.0 * h / o.num_headings + rng.Uniform(0.0, 360.0 / o.num_headings);
      const Rigid3d world_from_rig = RigFromWorldAt(position, heading).Inverse();
      if (o.travel_m > 0) {
        const auto ahead = caster.Cast(position, HeadingDirection(heading), o.travel_m + o.min_clearance_m);
        if (ahead) continue;
      }
      bool clear = true;
      int hits = 0, probes = 0;
      for (const RigCamera& rc : rig.cameras) {
        const Rigid3d world_from_cam = world_from_rig * rc.cam_from_rig->Inverse();
        const Eigen::Vector3d centre = world_from_cam.translation;
        for (const Eigen::Vector3d& d : central) {
          if (caster.Cast(centre, world_from_cam.rotation * d, o.min_clearance_m)) {
            clear = false;
            break;
          }
        }
        if (!clear) break;
        for (const Eigen::Vector3d& d : fan) {
          ++probes;
          const auto hit = caster.Cast(centre, world_from_cam.rotation * d, o.max_range_m);
          if (hit && hit->t >= o.min_clearance_m) ++hits;
        }
      }
      if (!clear) continue;
      const double score = double(hits) / std::max(1, probes);
      if (best && score <= best->score) continue;
      if (path) {  // the whole path from here, checked only for a new best (it costs more rays)
        TrajectoryOptions from_here = *path;
        from_here.start_world = position;
        from_here.heading_deg = heading;
        if (!PathIsClear(caster, rig, MakeTrajectory(from_here), o.height_m)) continue;
      }
      best = RigPlacement{position, heading, score, std::nullopt};
    }
  }
  return best;
}

std::optional<double> CastRay(const Scene& scene, const Eigen::Vector3d& origin, const Eigen::Vector3d& direction) {
  const GridCaster caster(scene);
  if (const auto hit = caster.Cast(origin, direction.normalized())) return hit->t;
  return std::nullopt;
}

}  // namespace rigsim
