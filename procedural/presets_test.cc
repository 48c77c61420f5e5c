#include "procedural/presets.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <set>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "gltf/gltf_loader.h"
#include "labels/cityscapes.h"
#include "procedural/glass_and_water.h"
#include "procedural/textures.h"
#include "scene/scene_pose.h"
#include "testing/temp_dir.h"

namespace rigsim {
namespace {

using procedural::kPi;

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

TEST(ScenePresets, AnimatedWritesLinearChannelsAndKeepsTheGeometry) {
  for (ScenePreset p : AllScenePresets()) {
    SCOPED_TRACE(std::string(ScenePresetName(p)));
    const nlohmann::json doc = GlbJson(ScenePresetGlb({p, 3, true}));
    ASSERT_TRUE(doc.contains("animations"));
    const auto& anim = doc["animations"][0];
    ASSERT_GE(anim["channels"].size(), 2u);
    std::set<std::string> paths;
    for (const auto& ch : anim["channels"]) {
      paths.insert(ch["target"]["path"].get<std::string>());
      const auto& node = doc["nodes"][ch["target"]["node"].get<int>()];
      EXPECT_TRUE(node.contains("translation"));
      EXPECT_FALSE(node.contains("matrix"));  // glTF: animated nodes use TRS
    }
    EXPECT_EQ(paths, (std::set<std::string>{"translation", "rotation"}));
    for (const auto& smp : anim["samplers"]) EXPECT_EQ(smp["interpolation"], "LINEAR");
    const nlohmann::json still = GlbJson(ScenePresetGlb({p, 3, false}));
    EXPECT_FALSE(still.contains("animations"));
    EXPECT_EQ(still["nodes"].size(), doc["nodes"].size());  // the default traffic adds no car
    // Every static node is the same node in the animated file (names in order).
    for (size_t i = 0; i < still["nodes"].size(); ++i) ASSERT_EQ(still["nodes"][i]["name"], doc["nodes"][i]["name"]) << i;
  }
}

// How an animated preset moves between two times: per class, the nodes' displacement of their
// origins (world, metres) and the largest tilt of their up axis from the vertical.
struct NodeMotion {
  std::string name;
  float moved_m = 0;      // horizontal distance between the two times
  float lean_rad = 0;     // up axis from the vertical at the first time
  bool turned = false;    // the rotation differs between the times
};
std::map<std::string, std::vector<NodeMotion>> MotionBetween(const Scene& s, double t0, double t1) {
  std::map<int, std::string> class_of_node;
  for (const SceneMesh& m : s.meshes) {
    if (m.node >= 0) class_of_node[m.node] = std::string(FindClassById(m.class_id)->name);
  }
  const std::vector<Eigen::Matrix4d> a = NodeWorldTransformsAt(s, t0), b = NodeWorldTransformsAt(s, t1);
  std::map<std::string, std::vector<NodeMotion>> out;
  for (const auto& [node, cls] : class_of_node) {
    NodeMotion m;
    m.name = s.nodes[node].name;
    m.moved_m = float(std::hypot(b[node](0, 3) - a[node](0, 3), b[node](2, 3) - a[node](2, 3)));
    m.lean_rad = float(std::acos(std::min(1.0, a[node](1, 1))));
    m.turned = !a[node].topLeftCorner<3, 3>().isApprox(b[node].topLeftCorner<3, 3>(), 1e-9);
    out[cls].push_back(m);
  }
  return out;
}

const std::vector<NodeMotion>& Of(const std::map<std::string, std::vector<NodeMotion>>& motion, const std::string& cls) {
  static const std::vector<NodeMotion> none;
  const auto it = motion.find(cls);
  return it == motion.end() ? none : it->second;
}

Scene LoadPreset(const ScenePresetOptions& o) {
  const TempDir dir;
  WriteScenePreset(o, dir / "scene.glb");
  return LoadGltf(dir / "scene.glb");
}

// Between 1.0 s and 1.5 s: people walk 0.6 to 0.75 m (1.2 to 1.5 m/s), driving cars 4 m (8 m/s),
// trees lean by at most 3 degrees and turn; at traffic 0 no vehicle moves.
TEST(ScenePresets, AnimatedWorldsMoveAsTheyShould) {
  const std::map<ScenePreset, int> cars_at_default = {{ScenePreset::kStreet, 5}, {ScenePreset::kPlaza, 0}, {ScenePreset::kParking, 2}};
  for (ScenePreset p : AllScenePresets()) {
    SCOPED_TRACE(std::string(ScenePresetName(p)));
    const Scene s = LoadPreset({p, 4, true});
    EXPECT_TRUE(s.warnings.empty()) << s.warnings.front();
    const auto motion = MotionBetween(s, 1.0, 1.5);
    int walking = 0;
    for (const NodeMotion& m : motion.at("person")) {
      EXPECT_LE(m.moved_m, 0.75f + 1e-3f) << m.name;
      walking += m.moved_m > 0.6f - 1e-3f;
    }
    EXPECT_GE(walking, int(0.7 * motion.at("person").size())) << "people at walking speed";
    int driving = 0;
    for (const NodeMotion& m : Of(motion, "car")) {
      if (m.moved_m == 0) continue;
      if (m.moved_m < 50) {  // else it looped back to its lane's start
        EXPECT_NEAR(m.moved_m, 4.f, 1e-3f) << m.name;
      }
      ++driving;
    }
    EXPECT_EQ(driving, cars_at_default.at(p));
    for (const NodeMotion& m : Of(motion, "bus")) EXPECT_NEAR(m.moved_m, 3.f, 1e-3f) << m.name;  // 6 m/s
    for (const NodeMotion& m : motion.at("vegetation")) {
      EXPECT_EQ(m.moved_m, 0.f) << m.name;  // about its base
      EXPECT_LE(m.lean_rad, 3.f * kPi / 180 + 1e-4f) << m.name;
      EXPECT_TRUE(m.turned) << m.name;
    }
    // The same world without traffic: no car or bus is animated, people still walk.
    const auto calm = MotionBetween(LoadPreset({p, 4, true, 0.0}), 1.0, 1.5);
    EXPECT_TRUE(Of(calm, "car").empty());
    EXPECT_TRUE(Of(calm, "bus").empty());
    EXPECT_EQ(Of(calm, "person").size(), motion.at("person").size());
  }
}

TEST(ScenePresets, MoreTrafficMovesMoreCars) {
  for (ScenePreset p : {ScenePreset::kStreet, ScenePreset::kParking}) {
    SCOPED_TRACE(std::string(ScenePresetName(p)));
    const auto motion = MotionBetween(LoadPreset({p, 4, true, 6.0}), 1.0, 1.5);
    int driving = 0;
    for (const NodeMotion& m : Of(motion, "car")) driving += m.moved_m > 3.99f;
    EXPECT_EQ(driving, p == ScenePreset::kStreet ? 14 : 7);  // 6 per 100 m of 240 m and 120 m of lane
  }
  EXPECT_THROW(ScenePresetGlb({ScenePreset::kStreet, 1, true, -1.0}), std::invalid_argument);
  EXPECT_THROW(ScenePresetGlb({ScenePreset::kStreet, 1, true, kMaxTraffic + 1}), std::invalid_argument);
}

TEST(ScenePresets, AnimationIsDeterministicPerSeed) {
  const ScenePresetOptions o{ScenePreset::kStreet, 5, true, 4.0};
  EXPECT_TRUE(ScenePresetGlb(o) == ScenePresetGlb(o));
  const nlohmann::json a = GlbJson(ScenePresetGlb(o)), b = GlbJson(ScenePresetGlb({ScenePreset::kStreet, 6, true, 4.0}));
  EXPECT_NE(a["animations"], b["animations"]);
}

TEST(ScenePresets, SeedChangesTheScene) {
  EXPECT_NE(ScenePresetGlb({ScenePreset::kPlaza, 1, false}), ScenePresetGlb({ScenePreset::kPlaza, 2, false}));
}

// A preset with glass and puddles: what each glossy primitive is, and that the rest is the world
// without them.
TEST(ScenePresets, GlassAndWetAddGlossyPartsAndKeepTheRest) {
  const uint8_t building = FindClassByName("building")->id;
  for (ScenePreset p : AllScenePresets()) {
    SCOPED_TRACE(std::string(ScenePresetName(p)));
    ScenePresetOptions o{p, 2, false};
    const Scene dry = LoadPreset(o);
    o.glass = true;
    o.wet = 0.15;
    const Scene wet = LoadPreset(o);
    EXPECT_TRUE(wet.warnings.empty()) << wet.warnings.front();
    std::vector<const SceneMesh*> rest;
    int glass = 0, puddles = 0;
    for (const SceneMesh& m : wet.meshes) {
      const Material& mat = wet.materials[size_t(m.material)];
      if (mat.roughness >= 1.f) {
        rest.push_back(&m);
        continue;
      }
      EXPECT_EQ(mat.metallic, 0.f) << m.name;  // glass and water are dielectrics
      // It lies over the texture of the primitive it belongs to: the same node's first one.
      const auto owner = std::find_if(wet.meshes.begin(), wet.meshes.end(), [&](const SceneMesh& o) { return o.instance_id == m.instance_id; });
      ASSERT_NE(&*owner, &m) << m.name;
      EXPECT_EQ(owner->class_id, m.class_id) << m.name;  // its class and instance
      EXPECT_EQ(mat.base_color_texture, wet.materials[size_t(owner->material)].base_color_texture) << m.name;
      if (m.class_id == building) {
        ++glass;
        EXPECT_FLOAT_EQ(mat.roughness, procedural::kWindowGlassRoughness) << m.name;
        EXPECT_FLOAT_EQ(mat.base_color_factor.x(), procedural::kWindowGlassShade) << m.name;
      } else {
        ++puddles;
        const std::string cls(FindClassById(m.class_id)->name);
        EXPECT_TRUE(cls == "road" || cls == "parking") << m.name << " is " << cls;
        EXPECT_FLOAT_EQ(mat.roughness, procedural::kPuddleRoughness) << m.name;
        EXPECT_FLOAT_EQ(mat.base_color_factor.x(), procedural::kPuddleShade) << m.name;
      }
    }
    EXPECT_GT(glass, 10);
    if (p == ScenePreset::kPlaza) {
      EXPECT_EQ(puddles, 0);  // paved, no road
    } else {
      EXPECT_GT(puddles, 3);
    }
    // Everything else is the dry world's, primitive by primitive.
    ASSERT_EQ(rest.size(), dry.meshes.size());
    for (size_t i = 0; i < rest.size(); ++i) {
      EXPECT_EQ(rest[i]->name, dry.meshes[i].name);
      EXPECT_EQ(rest[i]->class_id, dry.meshes[i].class_id);
      EXPECT_EQ(rest[i]->positions, dry.meshes[i].positions) << rest[i]->name;
    }
  }
}

TEST(ScenePresets, GlassAndWetAreSeeded) {
  ScenePresetOptions o{ScenePreset::kStreet, 4, false};
  o.glass = true;
  o.wet = 0.1;
  const std::vector<uint8_t> glb = ScenePresetGlb(o);
  EXPECT_TRUE(glb == ScenePresetGlb(o));
  ScenePresetOptions other = o;
  other.seed = 5;
  EXPECT_NE(glb, ScenePresetGlb(other));
  // Without them the world is the one of old: the shipped scenes' tests (ShippedAssetsMatchTheCode,
  // StreetPresetIsTheBuiltInStreet) generate them with these defaults.
  EXPECT_FALSE(ScenePresetOptions().glass);
  EXPECT_EQ(ScenePresetOptions().wet, 0.0);
}

TEST(ScenePresets, WetOutsideItsRangeIsRefused) {
  for (const double wet : {-0.1, kMaxWet + 0.01, std::nan("")}) {
    ScenePresetOptions o;
    o.wet = wet;
    try {
      o.Check();
      ADD_FAILURE() << wet << " accepted";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find("wet must be between 0 and 0.2"), std::string::npos) << e.what();
    }
  }
}

}  // namespace
}  // namespace rigsim
