// Rigs in a loaded scene: automatic placement (a free spot on the ground and a heading from which
// every camera sees structure), ring rigs spaced for a ground-truth overlap the scene decides, and
// single rays. All by brute-force ray casting over a coarse grid (rigs/grid_caster.h), not the
// renderer. Everything random takes an explicit seed.
//
// World: glTF's (+Y up, metres). Headings as in rigs/trajectories.h (0 = world -Z, 90 = world +X).
#pragma once

#include <cstdint>
#include <optional>

#include <Eigen/Core>

#include "geometry/rig.h"
#include "geometry/rigid3.h"
#include "rigs/rig_presets.h"
#include "rigs/trajectories.h"
#include "scene/scene.h"

namespace rigsim {

// Ring rig whose neighbours share `options.target_overlap` of their surface pixels as the
// renderer's ground truth counts it (overlap.json: sky excluded, depth-tested; the smaller of the
// two directions, the figure render and calibrate report), predicted by ray
// casting in `scene` with the rig at `rig_from_world`: cam0 keeps the yaw of the angular solution
// and each next camera's yaw is solved in turn, so spacings differ where the scene does (more sky
// or near occluders on one side). Costs a few seconds of ray casting.
Rig MakeRingRigInScene(const RingRigOptions& options, const Scene& scene, const Rigid3d& rig_from_world);

// Predicted ground-truth overlap of cameras a and b of `rig` at `rig_from_world` in `scene`
// (the smaller of both directions; see MakeRingRigInScene).
double PredictedOverlap(const Scene& scene, const Rig& rig, int a, int b, const Rigid3d& rig_from_world);
// PredictedOverlap of every pair of cameras (a symmetric matrix, zero diagonal), casting in one grid.
Eigen::MatrixXd PredictedOverlaps(const Scene& scene, const Rig& rig, const Rigid3d& rig_from_world);

struct PlacementOptions {
  double height_m = 1.6;          // rig origin above the ground under it
  double min_clearance_m = 2.0;   // no surface closer than this along any camera's central rays
  double travel_m = 0.0;          // free distance needed straight ahead (for a straight trajectory)
  double max_range_m = 80.0;      // hits further than this do not count as structure
  int num_candidates = 300;       // random positions tried (seeded)
  int num_headings = 24;          // headings tried at each position
  uint64_t seed = 1;
  void Check() const;             // throws std::invalid_argument
};

struct RigPlacement {
  Eigen::Vector3d position_world;
  double heading_deg = 0.0;
  double score = 0.0;  // fraction of probe rays of all cameras that hit structure in range
};

// Picks a position on the ground (the surface seen from above must be the lowest level of the
// scene, so not a roof or a car) and a heading such that the rig is not inside geometry, every
// camera's central rays see no surface closer than min_clearance_m, and as many probe rays as
// possible hit structure. With `path` (its start and heading replaced by the candidate's), the
// rig must also stay clear along the whole path: at every frame on the ground and not against
// geometry, and no surface across the moves of its centre and cameras between frames or across its
// arms to the cameras; a blocked path moves the rig to the next best candidate. Deterministic for
// a seed. nullopt when no candidate qualifies.
std::optional<RigPlacement> PlaceRig(const Scene& scene, const Rig& rig, const PlacementOptions& options,
                                     const TrajectoryOptions* path = nullptr);

// Distance to the first surface along a ray (unit direction), or nullopt. For tests and tools;
// builds the grid on each call, so use PlaceRig for many rays.
std::optional<double> CastRay(const Scene& scene, const Eigen::Vector3d& origin, const Eigen::Vector3d& direction);

}  // namespace rigsim
