// Checks that a Scene is consistent before anything is built from it: texture sizes match their
// bytes, every index points into what it indexes, and per-vertex attributes come one per position.
// The renderer relies on these checks (it reads the arrays without bounds checks); a scene from
// the glTF loader passes them, one assembled in code may not.
#pragma once

#include <string>
#include <vector>

#include "scene/scene.h"

namespace rigsim {

// How messages name a scene: its file, or "scene" when it was assembled in memory.
std::string SceneName(const Scene& scene);

// The scene's textures (a positive size, RGBA8 bytes for exactly that size), then its meshes
// (ValidateMeshes). Throws std::invalid_argument naming the scene, the texture or mesh, and what
// is wrong; the first fault found is reported.
void ValidateScene(const Scene& scene);

// `meshes` against the materials and textures of `scene` (its own meshes, or a posed copy of them,
// scene/scene_pose.h): whole triangles with indices into the positions, per-vertex attributes
// empty or one per position, and a material index (and that material's texture indices) in range.
void ValidateMeshes(const Scene& scene, const std::vector<SceneMesh>& meshes);

}  // namespace rigsim
