// Rigs in a loaded scene: automatic placement (a free spot on the ground and a heading from which
// every camera sees structure, or a vehicle's lane on the scene's road), ring rigs spaced for a ground-truth overlap the scene decides, and
// single rays. All by brute-force ray casting over a coarse grid (rigs/grid_caster.h), not the
// renderer. Everything random takes an explicit seed.
//
// World: glTF's (+Y up, metres). Headings as in rigs/trajectories.h (0 = world -Z, 90 = world +X).
#pragma once

#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string_view>

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

// How the placement chooses where the rig stands.
enum class PlacementMode {
  // A free spot on the ground (the scene's lowest level) and a heading from which every camera
  // sees as much structure as possible, clear of surfaces along every camera's axis.
  kStructure,
  // A vehicle in its lane: on a surface labelled road (Cityscapes 'road'), heading along the
  // road's long direction (either way), a quarter of the road's width right of its centre line
  // (right-hand traffic) where the road is wide enough for two lanes, else on the centre line.
  kRoad,
};
inline constexpr PlacementMode kAllPlacementModes[] = {PlacementMode::kStructure, PlacementMode::kRoad};
// "structure", "road".
std::string_view PlacementModeName(PlacementMode mode);
// Inverse of PlacementModeName; throws std::invalid_argument naming the modes.
PlacementMode PlacementModeFromName(std::string_view name);

// PlaceRig in road mode, in a scene where no surface is labelled road; what() says so and names
// the classes of the scene's ground (the lowest surface seen from above) by their share of it.
class NoRoadError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct PlacementOptions {
  PlacementMode mode = PlacementMode::kStructure;
  double height_m = 1.6;          // rig origin above the ground under it
  // No surface closer than this along any camera's central rays; road: along the lane ahead,
  // beyond the straight path's travel (the side cameras of a car in its lane may face a parked car).
  double min_clearance_m = 2.0;
  double travel_m = 0.0;          // free distance needed straight ahead (for a straight trajectory)
  double max_range_m = 80.0;      // hits further than this do not count as structure
  int num_candidates = 300;       // random positions tried (seeded); road: random spots on the road
  int num_headings = 24;          // headings tried at each position (structure only)
  // Road: the rig's footprint, this far to each side of its centre, stays on the road along the
  // whole path (half a car's width).
  double half_width_m = 1.0;
  // Road: a road at least this wide has a lane each way (two of 2.75 m, the narrowest urban lanes).
  double two_lane_width_m = 5.5;
  uint64_t seed = 1;
  void Check() const;             // throws std::invalid_argument
};

// Road mode: the road where the rig stands, measured on the scene's road labels.
struct RoadSpot {
  double width_m = 0.0;         // across the road through the rig, perpendicular to its long direction
  double lane_offset_m = 0.0;   // from the road's centre line to the rig's centre, to its right
  // The lane ahead of the rig: on the road and free of geometry for the rig's footprint (up to
  // max_range_m).
  double clear_ahead_m = 0.0;
  double clear_behind_m = 0.0;  // and behind it
};

struct RigPlacement {
  Eigen::Vector3d position_world;
  double heading_deg = 0.0;
  // Structure: the fraction of probe rays of all cameras that hit structure in range. Road: the
  // smaller of clear_ahead_m and clear_behind_m over max_range_m (the middle of a long stretch).
  double score = 0.0;
  std::optional<RoadSpot> road;  // road mode only
};

// Picks a position on the ground (the surface seen from above must be the lowest level of the
// scene, so not a roof or a car) and a heading such that the rig is not inside geometry, every
// camera's central rays see no surface closer than min_clearance_m, and as many probe rays as
// possible hit structure. With `path` (its start and heading replaced by the candidate's), the
// rig must also stay clear along the whole path: at every frame on the ground and not against
// geometry, and no surface across the moves of its centre and cameras between frames or across its
// arms to the cameras; a blocked path moves the rig to the next best candidate. Deterministic for
// a seed. nullopt when no candidate qualifies.
// Road mode (options.mode): random spots on the road labels instead, each moved to its lane,
// headed along the road both ways and scored by the clear road ahead and behind; the path must
// also keep the rig's footprint (half_width_m to each side) on the road all along (sampled every
// 0.5 m at most), and the same clearance checks apply, except along the camera axes
// (min_clearance_m is kept ahead of a straight path). Throws NoRoadError when no surface of the
// scene is labelled road.
std::optional<RigPlacement> PlaceRig(const Scene& scene, const Rig& rig, const PlacementOptions& options,
                                     const TrajectoryOptions* path = nullptr);

// Distance to the first surface along a ray (unit direction), or nullopt. For tests and tools;
// builds the grid on each call, so use PlaceRig for many rays.
std::optional<double> CastRay(const Scene& scene, const Eigen::Vector3d& origin, const Eigen::Vector3d& direction);

}  // namespace rigsim
