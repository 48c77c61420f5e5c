// A Scene made ready to render: the mip pyramids of its textures, each mesh's shading data, the
// Embree scene, and the pixel-centre rays of the cameras rendered so far. What Renderer holds;
// internal to the renderer (it holds Embree handles).
#pragma once

#include <algorithm>
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
  // Replaces the geometry by meshes posed at evenly spaced times over [t_begin, t_end]
  // (Renderer::SetMeshesOverTime; checked there).
  void SetMeshesOverTime(const std::vector<std::vector<SceneMesh>>& posed, double t_begin, double t_end);

  // Embree's ray time [0, 1] of a scene time: 0 without moving geometry.
  float RayTime(double time_s) const {
    if (!(motion_end_s > motion_begin_s)) return 0.0f;
    return float(std::clamp((time_s - motion_begin_s) / (motion_end_s - motion_begin_s), 0.0, 1.0));
  }

  const Scene& scene;               // materials and textures; meshes may come from SetMeshes
  MaterialTextures textures;
  std::vector<MeshShading> meshes;  // index == Embree geomID
  EmbreeScene embree;
  PixelCentreRayCache centre_rays;
  double motion_begin_s = 0.0, motion_end_s = 0.0;  // the moving geometry's time span; equal: none
  bool glossy = false;  // some mesh reflects the world (MeshShading::gloss > 0): Render runs SpecularBounce
};

}  // namespace rigsim
