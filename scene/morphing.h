// Morph targets (glTF 2.0, "Morph Targets"): a vertex's position is its base position plus the
// weighted sum of its targets' displacements, its normal the normalised sum likewise, all in the
// mesh's own frame and before skinning. The loader applies the rest weights; PoseSceneAt
// (scene/scene_pose.h) applies animated ones with this.
#pragma once

#include <vector>

#include "scene/scene.h"

namespace rigsim {

// Sets mesh->local_positions and local_normals from mesh->morph_base_positions, morph_base_normals
// and morph_targets with one weight per target. A normal that sums to zero keeps its base
// direction. Throws std::invalid_argument naming the mesh when the weights or a target's size do
// not fit.
void MorphMesh(const std::vector<double>& weights, SceneMesh* mesh);

}  // namespace rigsim
