#include "gltf/gltf_loader.h"

#include <numbers>
#include <vector>

#include <Eigen/Core>
#include <gtest/gtest.h>

#include "gltf/gltf_test_support.h"

namespace rigsim::gltf_test {
namespace {

TEST(GltfLoader, UnlitMaterialsAreMarked) {
  const TempDir dir;
  GltfBuilder g;
  const int pos = g.Positions(kUnitQuad);
  g.doc["extensionsUsed"] = {"KHR_materials_unlit"};
  g.doc["extensionsRequired"] = {"KHR_materials_unlit"};  // honoured, so not refused
  g.doc["materials"] = json::array({{{"name", "lit"}},
                                    {{"name", "flat"}, {"extensions", {{"KHR_materials_unlit", json::object()}}}}});
  g.Node({{"mesh", g.Mesh({{"POSITION", pos}}, -1, 6, 0)}});
  g.Node({{"mesh", g.Mesh({{"POSITION", pos}}, -1, 6, 1)}});
  g.Scene({0, 1});
  const Scene s = LoadGltf(g.Write(dir, "unlit"));
  ASSERT_EQ(s.materials.size(), 2u);
  EXPECT_FALSE(s.materials[0].unlit);
  EXPECT_TRUE(s.materials[1].unlit);
  EXPECT_FALSE(HasWarning(s, "unlit"));
}

// pbrMetallicRoughness's factors reach the scene (glTF's defaults, 1 and 1, when absent); a factor
// outside [0, 1] is refused, naming the material.
TEST(GltfLoader, MetallicAndRoughnessFactorsAreRead) {
  const TempDir dir;
  GltfBuilder g;
  const int pos = g.Positions(kUnitQuad);
  g.doc["materials"] = json::array({{{"name", "plain"}},
                                    {{"name", "paint"}, {"pbrMetallicRoughness", {{"metallicFactor", 0.25}, {"roughnessFactor", 0.1}}}}});
  g.Node({{"mesh", g.Mesh({{"POSITION", pos}}, -1, 6, 0)}});
  g.Node({{"mesh", g.Mesh({{"POSITION", pos}}, -1, 6, 1)}});
  g.Scene({0, 1});
  const Scene s = LoadGltf(g.Write(dir, "glossy"));
  ASSERT_EQ(s.materials.size(), 2u);
  EXPECT_EQ(s.materials[0].metallic, 1.0f);
  EXPECT_EQ(s.materials[0].roughness, 1.0f);
  EXPECT_EQ(s.materials[1].metallic, 0.25f);
  EXPECT_EQ(s.materials[1].roughness, 0.1f);
  g.doc["materials"][1]["pbrMetallicRoughness"]["roughnessFactor"] = 1.5;
  ExpectLoadFails(g.Write(dir, "too_rough"), "material 1 'paint': pbrMetallicRoughness roughnessFactor must be in [0, 1]");
  g.doc["materials"][1]["pbrMetallicRoughness"]["roughnessFactor"] = 0.1;
  g.doc["materials"][1]["pbrMetallicRoughness"]["metallicFactor"] = -0.5;
  ExpectLoadFails(g.Write(dir, "negative_metal"), "material 1 'paint': pbrMetallicRoughness metallicFactor must be in [0, 1]");
}

// emissiveFactor times KHR_materials_emissive_strength, and an emissive texture sampled through its
// own texCoord and KHR_texture_transform, baked apart from the base colour's coordinates.
TEST(GltfLoader, EmissionIsReadWithItsStrengthAndItsOwnTexcoords) {
  const TempDir dir;
  GltfBuilder g;
  const auto [pos, uv0, uv1] = g.QuadWithTwoTexcoordSets();
  g.doc["extensionsUsed"] = {"KHR_materials_emissive_strength", "KHR_texture_transform"};
  g.doc["extensionsRequired"] = {"KHR_materials_emissive_strength"};  // honoured, so not refused
  g.TinyTexture();
  g.doc["materials"] = json::array({
      {{"name", "sign"},
       {"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}},
       {"emissiveFactor", {0.5, 0.25, 0}},
       {"emissiveTexture", {{"index", 0}, {"texCoord", 1}, {"extensions", {{"KHR_texture_transform", {{"offset", {1, 0}}}}}}}},
       {"extensions", {{"KHR_materials_emissive_strength", {{"emissiveStrength", 4}}}}}},
      {{"name", "dark"}, {"emissiveTexture", {{"index", 0}}}},  // factor 0: the texture adds nothing
  });
  g.Node({{"mesh", g.Mesh({{"POSITION", pos}, {"TEXCOORD_0", uv0}, {"TEXCOORD_1", uv1}}, -1, 4, 0)}});
  g.Node({{"mesh", g.Mesh({{"POSITION", pos}, {"TEXCOORD_0", uv0}}, -1, 4, 1)}});
  g.Scene({0, 1});
  const Scene s = LoadGltf(g.Write(dir, "emissive"));
  ASSERT_EQ(s.materials.size(), 2u);
  EXPECT_TRUE(s.materials[0].emissive.isApprox(Eigen::Vector3f(2, 1, 0)));
  EXPECT_EQ(s.materials[0].emissive_texture, 0);
  EXPECT_EQ(s.materials[1].emissive, Eigen::Vector3f::Zero());
  EXPECT_EQ(s.materials[1].emissive_texture, -1);
  ASSERT_EQ(s.meshes.size(), 2u);
  ASSERT_EQ(s.meshes[0].texcoords.size(), 4u);
  ASSERT_EQ(s.meshes[0].emissive_texcoords.size(), 4u);
  EXPECT_EQ(s.meshes[0].texcoords[1], Eigen::Vector2f(1, 0));               // TEXCOORD_0 as it is
  EXPECT_EQ(s.meshes[0].emissive_texcoords[1], Eigen::Vector2f(1.75f, 0.25f));  // TEXCOORD_1 + offset
  EXPECT_TRUE(s.meshes[1].emissive_texcoords.empty());
  EXPECT_FALSE(HasWarning(s, "emissive"));
  EXPECT_FALSE(HasWarning(s, "TEXCOORD_1")) << "the emissive texture samples it";

  g.doc["materials"][0]["extensions"]["KHR_materials_emissive_strength"]["emissiveStrength"] = -1;
  ExpectLoadFails(g.Write(dir, "negative_strength"), "material 0 'sign': KHR_materials_emissive_strength: emissiveStrength must be");
  g.doc["materials"][0]["extensions"]["KHR_materials_emissive_strength"]["emissiveStrength"] = 1;
  g.doc["materials"][0]["emissiveFactor"] = {0.5, -0.25, 0};
  ExpectLoadFails(g.Write(dir, "negative_factor"), "material 0 'sign': emissiveFactor must be finite and >= 0");
}

// The two-texcoord quad on one node, with the tiny texture and `material` as its only material.
GltfBuilder QuadWithMaterial(const json& material) {
  GltfBuilder g;
  const auto [pos, uv0, uv1] = g.QuadWithTwoTexcoordSets();
  g.TinyTexture();
  g.doc["materials"] = json::array({material});
  g.Node({{"mesh", g.Mesh({{"POSITION", pos}, {"TEXCOORD_0", uv0}, {"TEXCOORD_1", uv1}}, -1, 4, 0)}});
  g.Scene({0});
  return g;
}

// normalTexture: its scale, and its own texCoord baked into SceneMesh::normal_texcoords.
TEST(GltfLoader, NormalTextureIsReadWithItsScaleAndTexcoords) {
  const TempDir dir;
  GltfBuilder g = QuadWithMaterial({{"name", "bricks"}, {"normalTexture", {{"index", 0}, {"texCoord", 1}, {"scale", 0.5}}}});
  const Scene s = LoadGltf(g.Write(dir, "normal_map"));
  ASSERT_EQ(s.materials.size(), 1u);
  EXPECT_EQ(s.materials[0].normal_texture, 0);
  EXPECT_FLOAT_EQ(s.materials[0].normal_scale, 0.5f);
  ASSERT_EQ(s.meshes.size(), 1u);
  ASSERT_EQ(s.meshes[0].normal_texcoords.size(), 4u);
  EXPECT_EQ(s.meshes[0].normal_texcoords[1], Eigen::Vector2f(0.75f, 0.25f));
  EXPECT_FALSE(HasWarning(s, "normalTexture"));
  EXPECT_FALSE(HasWarning(s, "TEXCOORD_1"));
}

// occlusionTexture: its strength, and its own texCoord baked into SceneMesh::occlusion_texcoords;
// a strength outside glTF's [0, 1] is refused.
TEST(GltfLoader, OcclusionTextureIsReadWithItsStrengthAndTexcoords) {
  const TempDir dir;
  GltfBuilder g = QuadWithMaterial({{"name", "baked"}, {"occlusionTexture", {{"index", 0}, {"texCoord", 1}, {"strength", 0.25}}}});
  const Scene s = LoadGltf(g.Write(dir, "occlusion"));
  ASSERT_EQ(s.materials.size(), 1u);
  EXPECT_EQ(s.materials[0].occlusion_texture, 0);
  EXPECT_FLOAT_EQ(s.materials[0].occlusion_strength, 0.25f);
  ASSERT_EQ(s.meshes.size(), 1u);
  ASSERT_EQ(s.meshes[0].occlusion_texcoords.size(), 4u);
  EXPECT_EQ(s.meshes[0].occlusion_texcoords[1], Eigen::Vector2f(0.75f, 0.25f));
  EXPECT_FALSE(HasWarning(s, "occlusion"));
  EXPECT_FALSE(HasWarning(s, "TEXCOORD_1"));
  g.doc["materials"][0]["occlusionTexture"]["strength"] = 1.5;
  ExpectLoadFails(g.Write(dir, "strong"), "material 0 'baked' occlusionTexture: strength must be in [0, 1], got 1.5");
}

// KHR_texture_transform: uv' = offset + R(rotation) * (scale * uv), with the rotation
// counter-clockwise in glTF's v-down UV space: at 90 deg (1, 0) -> (0, -1), as the Khronos sample
// viewer and the TextureTransformTest model have it (see ParseTextureTransform).
TEST(GltfLoader, TextureTransformIsBakedIntoTexcoords) {
  const TempDir dir;
  GltfBuilder g;
  const auto [pos, uv0, uv1] = g.QuadWithTwoTexcoordSets();
  const double half_pi = std::numbers::pi / 2;
  g.doc["extensionsUsed"] = {"KHR_texture_transform"};
  g.doc["extensionsRequired"] = {"KHR_texture_transform"};
  g.TinyTexture();
  auto textured = [&](json texture_info) { return json{{"pbrMetallicRoughness", {{"baseColorTexture", texture_info}}}}; };
  auto transform = [](json t) { return json{{"index", 0}, {"extensions", {{"KHR_texture_transform", t}}}}; };
  g.doc["materials"] = json::array({
      textured(transform({{"rotation", half_pi}})),                                   // 0: rotation only
      textured(transform({{"offset", {0.5, 0.25}}, {"scale", {2, 3}}})),              // 1: offset and scale
      textured(transform({{"offset", {0, 1}}, {"rotation", half_pi}, {"scale", {0.5, 0.5}}})),  // 2: the spec's example
      textured(transform({{"texCoord", 1}})),                                         // 3: the override picks TEXCOORD_1
      textured({{"index", 0}, {"texCoord", 1}, {"extensions", {{"KHR_texture_transform", {{"texCoord", 0}}}}}}),  // 4: override back to 0
      textured({{"index", 0}, {"texCoord", 1}}),                                      // 5: plain texCoord 1
  });
  for (int m = 0; m < 6; ++m) {
    g.Mesh({{"POSITION", pos}, {"TEXCOORD_0", uv0}, {"TEXCOORD_1", uv1}}, -1, 4, m);
    g.Node({{"mesh", m}});
  }
  g.Scene({0, 1, 2, 3, 4, 5});
  const Scene s = LoadGltf(g.Write(dir, "transform"));
  ASSERT_EQ(s.meshes.size(), 6u);
  EXPECT_FALSE(HasWarning(s, "extension KHR_texture_transform")) << "the extension is supported, not ignored";
  auto expect_uv = [&](int mesh, std::vector<Eigen::Vector2f> expected) {
    ASSERT_EQ(s.meshes[mesh].texcoords.size(), expected.size()) << mesh;
    for (size_t i = 0; i < expected.size(); ++i) {
      EXPECT_TRUE(s.meshes[mesh].texcoords[i].isApprox(expected[i], 1e-6f) ||
                  (s.meshes[mesh].texcoords[i] - expected[i]).norm() < 1e-6f)
          << "mesh " << mesh << " vertex " << i << ": " << s.meshes[mesh].texcoords[i].transpose() << " expected "
          << expected[i].transpose();
    }
  };
  // (0,0) (1,0) (1,1) (0,1) turned 90 deg counter-clockwise in the v-down UV plane.
  expect_uv(0, {{0, 0}, {0, -1}, {1, -1}, {1, 0}});
  expect_uv(1, {{0.5f, 0.25f}, {2.5f, 0.25f}, {2.5f, 3.25f}, {0.5f, 3.25f}});
  // The spec's example "utilizes only the lower left quadrant of the source image": u in [0, 0.5],
  // v in [0.5, 1].
  expect_uv(2, {{0, 1}, {0, 0.5f}, {0.5f, 0.5f}, {0.5f, 1}});
  expect_uv(3, {{0.25f, 0.25f}, {0.75f, 0.25f}, {0.75f, 0.75f}, {0.25f, 0.75f}});
  expect_uv(4, {{0, 0}, {1, 0}, {1, 1}, {0, 1}});
  expect_uv(5, {{0.25f, 0.25f}, {0.75f, 0.25f}, {0.75f, 0.75f}, {0.25f, 0.75f}});
  EXPECT_TRUE(HasWarning(s, "vertex attribute TEXCOORD_0")) << "the set no texture samples is reported";
  for (const Material& m : s.materials) EXPECT_EQ(m.base_color_texture, 0);
}

TEST(GltfLoader, MalformedTextureTransformThrowsAndMissingSetWarns) {
  const TempDir dir;
  GltfBuilder g;
  const int pos = g.Positions(kUnitQuad);
  const int uv0 = g.Accessor<float>({0, 0, 1, 0, 1, 1, 0, 1}, kGltfFloat, "VEC2", 4);
  g.doc["images"] = json::array({{{"uri", TinyPngUri()}}});
  g.doc["textures"] = json::array({{{"source", 0}}});
  g.doc["materials"] = json::array({{{"name", "atlas"},
                                     {"pbrMetallicRoughness",
                                      {{"baseColorTexture", {{"index", 0}, {"extensions", {{"KHR_texture_transform", {{"texCoord", 2}}}}}}}}}}});
  g.Mesh({{"POSITION", pos}, {"TEXCOORD_0", uv0}}, -1, 4, 0);
  g.Node({{"mesh", 0}});
  g.Scene({0});
  const Scene s = LoadGltf(g.Write(dir, "missing_set"));
  ASSERT_EQ(s.meshes.size(), 1u);
  EXPECT_TRUE(s.meshes[0].texcoords.empty());
  EXPECT_TRUE(HasWarning(s, "without their texture's TEXCOORD_2"));

  auto& ext = g.doc["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"]["extensions"]["KHR_texture_transform"];
  ext = {{"scale", {1}}};
  ExpectLoadFails(g.Write(dir, "short_scale"), "material 0 'atlas' baseColorTexture: KHR_texture_transform: scale must be an array of 2 numbers");
  ext = {{"rotation", "quarter"}};
  ExpectLoadFails(g.Write(dir, "text_rotation"), "rotation must be a finite number");
  ext = {{"texCoord", -1}};
  ExpectLoadFails(g.Write(dir, "negative_set"), "texCoord must be a non-negative integer");
}

}  // namespace
}  // namespace rigsim::gltf_test
