#include "renderer/prepared_scene.h"

#include "scene/scene_validation.h"

namespace rigsim {

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
}

}  // namespace rigsim
