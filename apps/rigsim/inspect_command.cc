// rigsim inspect FILE.gltf|FILE.glb [--rules RULES.json]: what the loader understood of a file.
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <map>
#include <set>
#include <string>

#include "apps/rigsim/commands.h"
#include "apps/rigsim/render_support.h"
#include "common/format.h"
#include "gltf/gltf_loader.h"
#include "gltf/label_rules.h"
#include "labels/cityscapes.h"
#include "scene/scene.h"

namespace rigsim::cli {
namespace {

// Hooks for what Scene may expose (cameras, animations): printed when the member exists, "not
// loaded" otherwise, so this command needs no change when the loader grows them.
template <typename S>
std::string CamerasOf(const S& scene) {
  if constexpr (requires { scene.cameras.size(); }) {
    return std::to_string(scene.cameras.size());
  } else {
    return "not loaded (see warnings)";
  }
}

template <typename S>
std::string AnimationsOf(const S& scene) {
  if constexpr (requires { scene.animation_channels.front().times_s; }) {
    if (scene.animation_channels.empty()) return "none";
    std::set<int> nodes;
    double t0 = 1e300, t1 = -1e300;
    size_t weights = 0;  // channels of morph-target weights
    for (const auto& ch : scene.animation_channels) {
      nodes.insert(ch.node);
      if (ch.path == AnimationPath::kWeights) ++weights;
      if (!ch.times_s.empty()) {
        t0 = std::min(t0, ch.times_s.front());
        t1 = std::max(t1, ch.times_s.back());
      }
    }
    char buf[200];
    const std::string of_weights = weights ? " (" + std::to_string(weights) + " of morph weights)" : "";
    std::snprintf(buf, sizeof(buf), "%s%s on %s, keys from %.2f s to %.2f s", Count(scene.animation_channels.size(), "channel").c_str(),
                  of_weights.c_str(), Count(nodes.size(), "node").c_str(), t0, t1);
    return buf;
  } else {
    return "not loaded (see warnings)";
  }
}

// Primitives with morph targets, their targets, and how many of them have animated weights.
std::string MorphsOf(const Scene& scene) {
  size_t morphed = 0, targets = 0, animated = 0;
  for (const SceneMesh& m : scene.meshes) {
    if (m.num_morph_targets == 0) continue;
    ++morphed;
    targets += size_t(m.num_morph_targets);
    if (!m.morph_targets.empty()) ++animated;
  }
  if (morphed == 0) return "none";
  return Count(morphed, "primitive") + " with morph targets, " + Count(targets, "target") + " in all, " +
         std::to_string(animated) + " with animated weights";
}

const char* AlphaName(AlphaMode m) {
  switch (m) {
    case AlphaMode::kOpaque: return "OPAQUE";
    case AlphaMode::kMask: return "MASK";
    case AlphaMode::kBlend: return "BLEND";
  }
  return "?";
}

void PrintScene(const Scene& scene, const std::filesystem::path& path, const LabelRules* rules) {
  // A node is one instance, or under EXT_mesh_gpu_instancing one per entry of its accessors, each
  // with its own id: such nodes are counted by their instance 0.
  std::set<uint16_t> plain, instanced_nodes, gpu_instances;
  for (const SceneMesh& m : scene.meshes) {
    if (!m.instance_id) continue;
    (m.gpu_instance < 0 ? plain : gpu_instances).insert(m.instance_id);
    if (m.gpu_instance == 0) instanced_nodes.insert(m.instance_id);
  }
  std::printf("file        %s (%.1f MB)\n", path.string().c_str(), std::filesystem::file_size(path) / 1e6);
  if (rules) std::printf("label rules %s (%s)\n", rules->source().c_str(), Count(rules->rules().size(), "rule").c_str());
  if (gpu_instances.empty()) {
    std::printf("nodes       %zu with geometry (one instance each)\n", plain.size());
  } else {
    std::printf("nodes       %zu with geometry (%s, %zu of them from %s via EXT_mesh_gpu_instancing)\n",
                plain.size() + instanced_nodes.size(), Count(plain.size() + gpu_instances.size(), "instance").c_str(),
                gpu_instances.size(), Count(instanced_nodes.size(), "node").c_str());
  }
  const size_t coloured = std::count_if(scene.meshes.begin(), scene.meshes.end(), [](const SceneMesh& m) { return !m.colors.empty(); });
  const size_t skinned = std::count_if(scene.meshes.begin(), scene.meshes.end(), [](const SceneMesh& m) { return m.skin >= 0; });
  std::string kinds;
  if (coloured) kinds += std::to_string(coloured) + " with vertex colours";
  if (skinned) kinds += (kinds.empty() ? "" : ", ") + std::to_string(skinned) + " skinned";

  std::printf("primitives  %zu%s\n", scene.meshes.size(), kinds.empty() ? "" : (" (" + kinds + ")").c_str());
  std::printf("triangles   %zu\n", scene.NumTriangles());
  std::map<std::string, int> alpha;
  for (const Material& m : scene.materials) ++alpha[AlphaName(m.alpha_mode)];
  const size_t unlit = std::count_if(scene.materials.begin(), scene.materials.end(), [](const Material& m) { return m.unlit; });
  if (unlit) alpha["unlit"] = int(unlit);
  const size_t emissive = std::count_if(scene.materials.begin(), scene.materials.end(),
                                        [](const Material& m) { return m.emissive != Eigen::Vector3f::Zero(); });
  if (emissive) alpha["emissive"] = int(emissive);
  const size_t normal_mapped = std::count_if(scene.materials.begin(), scene.materials.end(),
                                             [](const Material& m) { return m.normal_texture >= 0; });
  if (normal_mapped) alpha["normal-mapped"] = int(normal_mapped);
  const size_t occluded = std::count_if(scene.materials.begin(), scene.materials.end(),
                                        [](const Material& m) { return m.occlusion_texture >= 0; });
  if (occluded) alpha["with occlusion"] = int(occluded);
  std::string alpha_text;
  for (const auto& [mode, n] : alpha) alpha_text += (alpha_text.empty() ? "" : ", ") + std::to_string(n) + " " + mode;
  std::printf("materials   %zu%s\n", scene.materials.size(), alpha_text.empty() ? "" : (" (" + alpha_text + ")").c_str());
  size_t texels = 0, with_alpha = 0;
  for (const Texture& t : scene.textures) {
    texels += size_t(t.width) * t.height;
    for (size_t i = 3; i < t.rgba.size(); i += 4) {
      if (t.rgba[i] != 255) {
        ++with_alpha;
        break;
      }
    }
  }
  std::printf("textures    %zu (%.1f Mtexels, %zu with transparent texels)\n", scene.textures.size(), texels / 1e6, with_alpha);
  std::printf("cameras     %s\n", CamerasOf(scene).c_str());
  std::printf("animations  %s\n", AnimationsOf(scene).c_str());
  std::printf("morphs      %s\n", MorphsOf(scene).c_str());
  std::string compressed;
  if (scene.draco_primitives) compressed += Count(scene.draco_primitives, "primitive") + " by KHR_draco_mesh_compression";
  if (scene.meshopt_views) {
    compressed += (compressed.empty() ? "" : ", ") + Count(scene.meshopt_views, "buffer view") + " by EXT_meshopt_compression";
  }
  std::printf("compressed  %s\n", compressed.empty() ? "none" : compressed.c_str());
  if (!scene.meshes.empty()) {
    Eigen::Vector3f lo = Eigen::Vector3f::Constant(1e30f), hi = -lo;
    for (const SceneMesh& m : scene.meshes) {
      for (const Eigen::Vector3f& p : m.positions) {
        lo = lo.cwiseMin(p);
        hi = hi.cwiseMax(p);
      }
    }
    std::printf("bounds      x [%.2f, %.2f]  y [%.2f, %.2f]  z [%.2f, %.2f] m (glTF +Y up)\n", lo.x(), hi.x(), lo.y(), hi.y(),
                lo.z(), hi.z());
  }

  struct ClassStats {
    size_t primitives = 0, triangles = 0;
    std::set<uint16_t> instances;
  };
  std::map<uint8_t, ClassStats> per_class;
  for (const SceneMesh& m : scene.meshes) {
    ClassStats& s = per_class[m.class_id];
    ++s.primitives;
    s.triangles += m.indices.size() / 3;
    if (m.instance_id) s.instances.insert(m.instance_id);
  }
  const double total = std::max<size_t>(1, scene.NumTriangles());
  std::printf("\n%-3s %-16s %-9s %10s %10s %10s %7s\n", "id", "class", "reliable", "instances", "primitives", "triangles", "share");
  for (const auto& [id, s] : per_class) {
    const LabelClass* c = FindClassById(id);
    std::printf("%-3d %-16s %-9s %10zu %10zu %10zu %6.1f%%\n", id, c ? std::string(c->name).c_str() : "?",
                c && c->reliable ? "yes" : "no", s.instances.size(), s.primitives, s.triangles, 100.0 * s.triangles / total);
  }
  std::printf("\n%s\n", Count(scene.warnings.size(), "warning").c_str());
  for (const std::string& w : scene.warnings) std::printf("  warning: %s\n", w.c_str());
}

}  // namespace

void AddInspectCommand(CLI::App& app) {
  struct Args {
    std::string file, rules;
  };
  auto args = std::make_shared<Args>();
  CLI::App* cmd = app.add_subcommand(
      "inspect",
      "Print what the glTF loader understood of a file: nodes, primitives, triangles, materials,\n"
      "textures, cameras, animations, triangles per class and every warning. Exits 0 when the file\n"
      "loads. Use --rules to try a label-rules file on a glTF without extras.class.");
  cmd->add_option("file", args->file, "glTF 2.0 file (.gltf or .glb)")->required()->check(CLI::ExistingFile);
  AddLabelRulesOption(*cmd, args->rules);
  cmd->callback([args] {
    std::optional<LabelRules> rules;
    GltfLoadOptions options;
    if (!args->rules.empty()) {
      rules = LabelRules::Read(args->rules);
      options.label_rules = &*rules;
    }
    const Scene scene = LoadGltf(args->file, options);
    PrintScene(scene, args->file, rules ? &*rules : nullptr);
  });
}

}  // namespace rigsim::cli
