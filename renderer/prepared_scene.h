// A Scene made ready to render: the mip pyramids of its textures, each mesh's shading data, the
// Embree scene, and the pixel-centre rays of the cameras rendered so far. What Renderer holds;
// internal to the renderer (it holds Embree handles).
#pragma once

#include <string>
#include <vector>

#include "renderer/camera_rays.h"
#include "renderer/embree_scene.h"
#include "renderer/shading.h"
#include "scene/scene.h"

namespace rigsim {

struct PreparedScene {
  // `scene` must have passed ValidateScene (scene/scene_validation.h) and outlive this object.
  // Throws std::runtime_error on an Embree failure.
  explicit PreparedScene(const Scene& scene);

  // Replaces the geometry by `meshes` (checked by ValidateMeshes against `scene`'s materials and
  // textures), which must outlive this object or the next SetMeshes. Textures are kept.
  void SetMeshes(const std::vector<SceneMesh>& meshes);

  const Scene& scene;               // materials and textures; meshes may come from SetMeshes
  MaterialTextures textures;
  std::vector<MeshShading> meshes;  // index == Embree geomID
  EmbreeScene embree;
  PixelCentreRayCache centre_rays;
};

}  // namespace rigsim
