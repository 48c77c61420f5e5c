#include "procedural/presets.h"

#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <set>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "gltf/gltf_loader.h"
#include "labels/cityscapes.h"

namespace rigsim {
namespace {

std::vector<uint8_t> ReadBytes(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  return std::vector<uint8_t>(std::istreambuf_iterator<char>(in), {});
}

// The JSON chunk of a .glb.
nlohmann::json GlbJson(const std::vector<uint8_t>& glb) {
  const uint32_t len = uint32_t(glb[12]) | uint32_t(glb[13]) << 8 | uint32_t(glb[14]) << 16 | uint32_t(glb[15]) << 24;
  return nlohmann::json::parse(std::string(glb.begin() + 20, glb.begin() + 20 + len));
}

std::filesystem::path AssetOf(ScenePreset p) { return "assets/scenes/" + std::string(ScenePresetName(p)) + ".glb"; }

TEST(ScenePresets, NamesRoundTrip) {
  for (ScenePreset p : AllScenePresets()) EXPECT_EQ(ScenePresetFromName(ScenePresetName(p)), p);
  EXPECT_THROW(ScenePresetFromName("beach"), std::invalid_argument);
}

TEST(ScenePresets, StreetPresetIsTheBuiltInStreet) {
  EXPECT_TRUE(ScenePresetGlb({ScenePreset::kStreet, 1, false}) == ReadBytes("assets/scenes/street.glb"));
}

TEST(ScenePresets, ShippedAssetsMatchTheCode) {
  for (ScenePreset p : {ScenePreset::kPlaza, ScenePreset::kParking}) {
    const auto asset = AssetOf(p);
    ASSERT_TRUE(std::filesystem::exists(asset)) << "run from the repository root";
    EXPECT_LT(std::filesystem::file_size(asset), 8u * 1024 * 1024) << asset;
    EXPECT_TRUE(ScenePresetGlb({p, 1, false}) == ReadBytes(asset))
        << asset << " is out of date: regenerate it with rigsim_make_street_scene " << asset << " 1 " << ScenePresetName(p);
  }
}

TEST(ScenePresets, LoadCleanlyWithTheirClasses) {
  const std::map<ScenePreset, std::vector<const char*>> expected = {
      {ScenePreset::kPlaza, {"sidewalk", "terrain", "building", "wall", "pole", "vegetation", "person", "bus"}},
      {ScenePreset::kParking, {"parking", "sidewalk", "road", "building", "wall", "fence", "pole", "car", "bus", "person", "vegetation"}}};
  for (const auto& [preset, names] : expected) {
    SCOPED_TRACE(std::string(ScenePresetName(preset)));
    const Scene s = LoadGltf(AssetOf(preset));
    EXPECT_TRUE(s.warnings.empty()) << s.warnings.front();
    std::set<uint8_t> classes;
    for (const SceneMesh& m : s.meshes) {
      classes.insert(m.class_id);
      EXPECT_NE(m.class_id, kUnlabeledId) << m.name;
    }
    for (const char* name : names) EXPECT_TRUE(classes.count(FindClassByName(name)->id)) << name;
    // Foliage is alpha-masked cards with real transparency.
    int masked = 0;
    for (const Material& m : s.materials) {
      if (m.alpha_mode != AlphaMode::kMask) continue;
      ++masked;
      ASSERT_GE(m.base_color_texture, 0);
      const Texture& t = s.textures[m.base_color_texture];
      size_t transparent = 0;
      for (size_t i = 3; i < t.rgba.size(); i += 4) transparent += t.rgba[i] < 128;
      EXPECT_GT(transparent, t.rgba.size() / 4 / 10) << t.name;
    }
    EXPECT_GE(masked, 2);
  }
}

TEST(ScenePresets, SemanticDistractorsAndIdenticalCars) {
  for (ScenePreset p : {ScenePreset::kPlaza, ScenePreset::kParking}) {
    SCOPED_TRACE(std::string(ScenePresetName(p)));
    const Scene s = LoadGltf(AssetOf(p));
    // The poster texture is shown by a bus and by a wall.
    std::map<int, std::set<uint8_t>> classes_per_texture;
    std::map<std::pair<int, size_t>, int> car_models;  // (material, vertex count) -> instances
    for (const SceneMesh& m : s.meshes) {
      if (m.material < 0) continue;
      classes_per_texture[s.materials[m.material].base_color_texture].insert(m.class_id);
      if (m.class_id == FindClassByName("car")->id) ++car_models[{m.material, m.positions.size()}];
    }
    bool distractor = false;
    for (const auto& [tex, classes] : classes_per_texture) {
      distractor = distractor || (classes.count(FindClassByName("bus")->id) && classes.count(FindClassByName("wall")->id));
    }
    EXPECT_TRUE(distractor);
    if (p == ScenePreset::kParking) {
      int most = 0;
      for (const auto& [key, n] : car_models) most = std::max(most, n);
      EXPECT_GE(most, 10) << "identical car models (same mesh and texture)";
    }
  }
}

TEST(ScenePresets, AnimatedWritesTranslationChannelsAndKeepsTheGeometry) {
  for (ScenePreset p : AllScenePresets()) {
    SCOPED_TRACE(std::string(ScenePresetName(p)));
    const nlohmann::json doc = GlbJson(ScenePresetGlb({p, 3, true}));
    ASSERT_TRUE(doc.contains("animations"));
    const auto& anim = doc["animations"][0];
    ASSERT_GE(anim["channels"].size(), 2u);
    for (const auto& ch : anim["channels"]) {
      EXPECT_EQ(ch["target"]["path"], "translation");
      const auto& node = doc["nodes"][ch["target"]["node"].get<int>()];
      EXPECT_TRUE(node.contains("translation"));
      EXPECT_FALSE(node.contains("matrix"));  // glTF: animated nodes use TRS
    }
    for (const auto& smp : anim["samplers"]) EXPECT_EQ(smp["interpolation"], "LINEAR");
    const nlohmann::json still = GlbJson(ScenePresetGlb({p, 3, false}));
    EXPECT_FALSE(still.contains("animations"));
    EXPECT_EQ(still["nodes"].size(), doc["nodes"].size());
  }
}

TEST(ScenePresets, SeedChangesTheScene) {
  EXPECT_NE(ScenePresetGlb({ScenePreset::kPlaza, 1, false}), ScenePresetGlb({ScenePreset::kPlaza, 2, false}));
}

}  // namespace
}  // namespace rigsim
