// The clearance checks that every placement applies (rigs/placement.h): whether a rig stands in
// geometry, and whether its path over the frames stays on the ground and out of the scene's
// geometry. By ray casting over a GridCaster.
#pragma once

#include <Eigen/Core>

#include "dataset/dataset.h"
#include "geometry/rig.h"
#include "rigs/grid_caster.h"

namespace rigsim {

// Whether something is within 0.5 m above `position` or 0.6 m around it horizontally: the rig would
// stand inside geometry or against it.
bool Boxed(const GridCaster& caster, const Eigen::Vector3d& position);

// Whether the straight segment from a to b crosses a surface.
bool SegmentHits(const GridCaster& caster, const Eigen::Vector3d& a, const Eigen::Vector3d& b);

// Whether a rig following `frames` stays clear of the scene: at every frame its centre stands on
// the ground (the first surface below it within 0.5 m of height_m) and is not Boxed, and no surface
// lies across the moves between frames of its centre and of every camera centre, nor across the
// rig's arms from its centre to each camera.
bool PathIsClear(const GridCaster& caster, const Rig& rig, const FramesFile& frames, double height_m);

}  // namespace rigsim
