#include "scene/scene_validation.h"

#include <cstdint>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace rigsim {
namespace {

void ValidateMesh(const Scene& scene, const SceneMesh& mesh, const std::string& where) {
  if (mesh.indices.size() % 3 != 0) throw std::invalid_argument(where + ": index count is not a multiple of 3");
  for (uint32_t index : mesh.indices) {
    if (index >= mesh.positions.size()) {
      throw std::invalid_argument(where + ": index " + std::to_string(index) + " >= " +
                                  std::to_string(mesh.positions.size()) + " positions");
    }
  }
  // Per-vertex attributes: none, or one per position.
  auto check_per_vertex = [&](size_t count, const char* what) {
    if (count != 0 && count != mesh.positions.size()) {
      throw std::invalid_argument(where + ": " + std::to_string(count) + " " + what + " for " +
                                  std::to_string(mesh.positions.size()) + " positions");
    }
  };
  check_per_vertex(mesh.normals.size(), "normals");
  check_per_vertex(mesh.texcoords.size(), "texcoords");
  check_per_vertex(mesh.normal_texcoords.size(), "normal-map texcoords");
  check_per_vertex(mesh.emissive_texcoords.size(), "emissive texcoords");
  check_per_vertex(mesh.occlusion_texcoords.size(), "occlusion texcoords");
  check_per_vertex(mesh.colors.size(), "vertex colours");
  if (mesh.material < -1 || mesh.material >= int(scene.materials.size())) {
    throw std::invalid_argument(where + ": material index " + std::to_string(mesh.material) + " out of range");
  }
  if (mesh.material < 0) return;
  // A material's textures are checked where a mesh uses it: an unused material is never read.
  const Material& material = scene.materials[mesh.material];
  auto check_texture = [&](int index, const char* what) {
    if (index >= int(scene.textures.size()) || index < -1) {
      throw std::invalid_argument(where + ": material '" + material.name + "' " + what + " index " +
                                  std::to_string(index) + " out of range");
    }
  };
  check_texture(material.base_color_texture, "texture");
  check_texture(material.emissive_texture, "emissive texture");
  check_texture(material.normal_texture, "normal texture");
  check_texture(material.occlusion_texture, "occlusion texture");
  for (const auto& [value, name] : {std::pair{material.metallic, "metallic"}, std::pair{material.roughness, "roughness"}}) {
    if (!(value >= 0.0f && value <= 1.0f)) {
      throw std::invalid_argument(where + ": material '" + material.name + "' " + name + " must be in [0, 1], got " +
                                  std::to_string(value));
    }
  }
}

void ValidateTextures(const Scene& scene) {
  for (const Texture& texture : scene.textures) {
    if (texture.width <= 0 || texture.height <= 0 ||
        texture.rgba.size() != size_t(texture.width) * texture.height * 4) {
      throw std::invalid_argument(SceneName(scene) + ": texture '" + texture.name + "' has size " +
                                  std::to_string(texture.width) + "x" + std::to_string(texture.height) + " but " +
                                  std::to_string(texture.rgba.size()) + " bytes (RGBA8 expected)");
    }
  }
}

}  // namespace

std::string SceneName(const Scene& scene) { return scene.source.empty() ? std::string("scene") : scene.source; }

void ValidateScene(const Scene& scene) {
  ValidateTextures(scene);
  ValidateMeshes(scene, scene.meshes);
}

void ValidateMeshes(const Scene& scene, const std::vector<SceneMesh>& meshes) {
  const std::string source = SceneName(scene);
  for (size_t i = 0; i < meshes.size(); ++i) {
    ValidateMesh(scene, meshes[i], source + ": mesh " + std::to_string(i) + " '" + meshes[i].name + "'");
  }
}

}  // namespace rigsim
