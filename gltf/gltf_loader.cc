#include "gltf/gltf_loader.h"

#include <string>

#include "gltf/loader.h"

namespace rigsim::gltf {

Scene Loader::Load() {
  ReadModel();
  scene_.source = path_.string();
  ReportFileLevelUnsupported();
  ParseClasses();
  ConvertMaterials();
  CheckNodeTransforms();
  ParseAnimations();
  ParseSkins();
  Traverse();
  SkinAtRestPose();
  Summarise();
  return std::move(scene_);
}

void Loader::Summarise() {
  ReportUnusedLabelRules();
  for (const auto& [what, count] : ignored_) Warn("not supported, ignored: " + what + " (" + std::to_string(count) + "x)");
  if (unlabeled_triangles_ > 0) {
    Warn(std::to_string(unlabeled_triangles_) + " triangles in " + std::to_string(unlabeled_meshes_) +
         " primitive(s) have no class (extras.class on node, mesh or material" +
         std::string(options_.label_rules ? ", or a label rule" : "") + ") and are unlabeled");
  }
}

}  // namespace rigsim::gltf

namespace rigsim {

Scene LoadGltf(const std::filesystem::path& path, const GltfLoadOptions& options) { return gltf::Loader(path, options).Load(); }

}  // namespace rigsim
