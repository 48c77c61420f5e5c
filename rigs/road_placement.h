// Road mode of PlaceRig (rigs/placement.h): a vehicle rig in its lane, heading along the road,
// found on the scene's road labels by ray casting. Its own header so that placement.cc stays the
// structure mode; callers use PlaceRig.
#pragma once

#include <optional>

#include "geometry/rig.h"
#include "rigs/grid_caster.h"
#include "rigs/placement.h"
#include "rigs/trajectories.h"
#include "scene/scene.h"

namespace rigsim {

// PlaceRig for PlacementMode::kRoad, options already checked. Throws NoRoadError.
std::optional<RigPlacement> PlaceRigOnRoad(const Scene& scene, const GridCaster& caster, const Rig& rig,
                                           const PlacementOptions& options, const TrajectoryOptions* path);

}  // namespace rigsim
