#include "gltf/scene_builder.h"

#include <cmath>
#include <filesystem>
#include <stdexcept>

#include <gtest/gtest.h>

#include "gltf/gltf_loader.h"
#include "labels/cityscapes.h"
#include "scene/scene_pose.h"
#include "testing/temp_dir.h"

namespace rigsim {
namespace {

MeshData Triangle() {
  MeshData m;
  m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  m.normals = {{0, 0, 1}, {0, 0, 1}, {0, 0, 1}};
  m.texcoords = {{0, 1}, {1, 1}, {0, 0}};
  m.indices = {0, 1, 2};
  return m;
}

TEST(SceneBuilder, RoundTripThroughLoader) {
  SceneBuilder b;
  std::vector<uint8_t> rgb(40 * 30 * 3);
  for (size_t i = 0; i < rgb.size(); ++i) rgb[i] = uint8_t((i * 7) % 251);
  const int tex_rgb = b.AddTexture("rgb", 40, 30, 3, rgb);
  std::vector<uint8_t> rgba(8 * 4 * 4, 200);
  rgba[3] = 10;  // not opaque: stored as PNG, alpha preserved exactly
  const int tex_rgba = b.AddTexture("rgba", 8, 4, 4, rgba, /*nearest=*/true);
  const int m0 = b.AddMaterial("paint", Eigen::Vector4f(1, 0.5f, 0.25f, 1), tex_rgb);
  const int m1 = b.AddMaterial("glass", Eigen::Vector4f::Ones(), tex_rgba, /*double_sided=*/true);
  b.AddNode("wall", "building", Triangle(), m0);
  Eigen::Matrix4d shift = Eigen::Matrix4d::Identity();
  shift(0, 3) = 10;
  b.AddNode("car", "car", Triangle(), m1, shift);
  std::vector<MeshPart> parts;
  parts.push_back({Triangle(), m0});
  parts.push_back({Triangle(), -1});
  b.AddNode("two_parts", "", std::move(parts));

  const TempDir dir;
  const auto path = dir / "scene.glb";
  b.WriteGlb(path);
  const Scene s = LoadGltf(path);
  ASSERT_EQ(s.meshes.size(), 4u);
  EXPECT_EQ(s.NumTriangles(), 4u);
  EXPECT_EQ(s.meshes[0].class_id, FindClassByName("building")->id);
  EXPECT_EQ(s.meshes[1].class_id, FindClassByName("car")->id);
  EXPECT_EQ(s.meshes[2].class_id, kUnlabeledId);
  EXPECT_EQ(s.meshes[0].instance_id, 1);
  EXPECT_EQ(s.meshes[1].instance_id, 2);
  EXPECT_EQ(s.meshes[2].instance_id, 3);
  EXPECT_EQ(s.meshes[3].instance_id, 3);  // both primitives of one node: one instance
  EXPECT_TRUE(s.meshes[1].positions[1].isApprox(Eigen::Vector3f(11, 0, 0)));
  EXPECT_TRUE(s.meshes[0].texcoords[2].isApprox(Eigen::Vector2f(0, 0)));
  ASSERT_EQ(s.textures.size(), 2u);
  EXPECT_EQ(s.textures[0].width, 40);
  EXPECT_EQ(s.textures[0].height, 30);
  EXPECT_EQ(s.textures[1].width, 8);
  EXPECT_EQ(s.textures[1].rgba[3], 10);
  EXPECT_TRUE(s.textures[1].nearest);
  // JPEG is lossy but close at quality 90 on a smooth-ish pattern: compare the mean error.
  double err = 0;
  for (int i = 0; i < 40 * 30; ++i) {
    for (int c = 0; c < 3; ++c) err += std::abs(int(s.textures[0].rgba[i * 4 + c]) - int(rgb[i * 3 + c]));
  }
  EXPECT_LT(err / (40 * 30 * 3), 40.0);
  EXPECT_EQ(s.textures[0].rgba[3], 255);
  ASSERT_EQ(s.materials.size(), 2u);
  EXPECT_TRUE(s.materials[0].base_color_factor.isApprox(Eigen::Vector4f(1, 0.5f, 0.25f, 1)));
  EXPECT_TRUE(s.materials[1].double_sided);
  // Only the class-less node is reported, once.
  int unlabeled_warnings = 0;
  for (const std::string& w : s.warnings) unlabeled_warnings += w.find("no class") != std::string::npos;
  EXPECT_EQ(unlabeled_warnings, 1);
}

TEST(SceneBuilder, SameCallsGiveSameBytes) {
  auto make = [] {
    SceneBuilder b;
    std::vector<uint8_t> rgb(16 * 16 * 3);
    for (size_t i = 0; i < rgb.size(); ++i) rgb[i] = uint8_t(i * 13);
    b.AddMaterial("m", Eigen::Vector4f::Ones(), b.AddTexture("t", 16, 16, 3, rgb));
    b.AddNode("n", "road", Triangle(), 0);
    return b.ToGlb();
  };
  const std::vector<uint8_t> a = make();
  EXPECT_EQ(a, make());
  ASSERT_GE(a.size(), 12u);
  EXPECT_EQ(std::string(a.begin(), a.begin() + 4), "glTF");
  EXPECT_EQ(a.size() % 4, 0u);
}

// A node with a translation and a rotation animation: both channels load, and posing the scene
// moves and turns the node's vertices as the keys say (rotation about the node's origin).
TEST(SceneBuilder, TranslationAndRotationAnimationsPoseTheNode) {
  SceneBuilder b;
  const int node = b.AddNode("walker", "person", Triangle(), -1);
  b.AddNode("ground", "road", Triangle(), -1);
  const Eigen::Quaternionf quarter(Eigen::AngleAxisf(float(M_PI / 2), Eigen::Vector3f::UnitY()));
  b.AddTranslationAnimation(node, {0.f, 2.f}, {Eigen::Vector3f(0, 0, 0), Eigen::Vector3f(4, 0, 0)});
  b.AddRotationAnimation(node, {0.f, 2.f}, {Eigen::Quaternionf::Identity(), quarter});
  EXPECT_THROW(b.AddRotationAnimation(node, {0.f}, {quarter}), std::invalid_argument);  // one per path
  EXPECT_THROW(b.AddRotationAnimation(1, {0.f, 1.f}, {quarter}), std::invalid_argument);
  EXPECT_THROW(b.AddRotationAnimation(1, {1.f, 1.f}, {quarter, quarter}), std::invalid_argument);
  EXPECT_THROW(b.AddRotationAnimation(1, {0.f}, {Eigen::Quaternionf(0, 0, 0, 0)}), std::invalid_argument);
  const TempDir dir;
  b.WriteGlb(dir / "moving.glb");
  const Scene s = LoadGltf(dir / "moving.glb");
  EXPECT_TRUE(s.warnings.empty()) << s.warnings.front();
  ASSERT_EQ(s.animation_channels.size(), 2u);
  EXPECT_EQ(s.animation_channels[0].path, AnimationPath::kTranslation);
  EXPECT_EQ(s.animation_channels[1].path, AnimationPath::kRotation);
  // At t = 2: turned 90 degrees about +Y (x -> -z), then moved 4 m along x.
  const std::vector<SceneMesh> end = PoseMeshesAt(s, 2.0);
  EXPECT_TRUE(end[0].positions[1].isApprox(Eigen::Vector3f(4, 0, -1), 1e-5f)) << end[0].positions[1].transpose();
  // Half way: 2 m along x and turned 45 degrees (slerp).
  const std::vector<SceneMesh> half = PoseMeshesAt(s, 1.0);
  const float c = std::sqrt(0.5f);
  EXPECT_TRUE(half[0].positions[1].isApprox(Eigen::Vector3f(2 + c, 0, -c), 1e-5f)) << half[0].positions[1].transpose();
  EXPECT_TRUE(end[1].positions[1].isApprox(Eigen::Vector3f(1, 0, 0)));  // the static node stays
}

TEST(SceneBuilder, RejectsBadInput) {
  SceneBuilder b;
  EXPECT_THROW(b.AddNode("x", "no such class", Triangle(), -1), std::invalid_argument);
  EXPECT_THROW(b.AddNode("x", "road", Triangle(), 3), std::invalid_argument);
  MeshData bad = Triangle();
  bad.indices = {0, 1, 5};
  EXPECT_THROW(b.AddNode("x", "road", bad, -1), std::invalid_argument);
  EXPECT_THROW(b.AddTexture("t", 4, 4, 3, std::vector<uint8_t>(10)), std::invalid_argument);
  EXPECT_THROW(b.WriteGlb("/nonexistent_dir_rigsim/x.glb"), std::runtime_error);
}

}  // namespace
}  // namespace rigsim
