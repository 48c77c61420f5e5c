#include "renderer/prepared_scene.h"

#include <algorithm>

#include "scene/scene_validation.h"

namespace rigsim {
namespace {

bool AnyGlossy(const std::vector<MeshShading>& meshes) {
  return std::any_of(meshes.begin(), meshes.end(), [](const MeshShading& m) { return m.gloss > 0.0f; });
}

}  // namespace

PreparedScene::PreparedScene(const Scene& scene)
    : scene(scene), textures(BuildMaterialTextures(scene)), embree(SceneName(scene)) {
  SetMeshes(scene.meshes);
}

void PreparedScene::SetMeshes(const std::vector<SceneMesh>& scene_meshes) {
  // The old scene and shading data go first: the new ones are not built beside them.
  embree.Release();
  meshes.clear();
  meshes.shrink_to_fit();
  meshes.reserve(scene_meshes.size());
  for (const SceneMesh& mesh : scene_meshes) meshes.push_back(PrepareMeshShading(mesh, scene, textures));
  embree.Build(scene_meshes, meshes);
  motion_begin_s = motion_end_s = 0.0;
  glossy = AnyGlossy(meshes);
}

void PreparedScene::SetMeshesOverTime(const std::vector<std::vector<SceneMesh>>& posed, double t_begin, double t_end) {
  embree.Release();
  meshes.clear();
  meshes.shrink_to_fit();
  const std::vector<SceneMesh>& middle = posed[posed.size() / 2];
  meshes.reserve(middle.size());
  for (const SceneMesh& mesh : middle) meshes.push_back(PrepareMeshShading(mesh, scene, textures));
  embree.Build(middle, meshes, &posed);
  motion_begin_s = t_begin;
  motion_end_s = t_end;
  glossy = AnyGlossy(meshes);
}

}  // namespace rigsim
