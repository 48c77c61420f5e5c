#include "scene/scene_validation.h"

#include <stdexcept>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "testing/expect_error.h"

namespace rigsim {
namespace {

// A scene from "broken.glb": one 2 x 2 texture, one material using it, and one textured quad.
Scene ValidScene() {
  Scene scene;
  scene.source = "broken.glb";
  Texture texture;
  texture.name = "bricks";
  texture.width = texture.height = 2;
  texture.rgba.assign(2 * 2 * 4, 255);
  scene.textures.push_back(texture);
  Material material;
  material.name = "wall";
  material.base_color_texture = 0;
  scene.materials.push_back(material);
  SceneMesh mesh;
  mesh.name = "quad";
  mesh.material = 0;
  mesh.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  mesh.texcoords = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  mesh.indices = {0, 1, 2, 0, 2, 3};
  scene.meshes.push_back(mesh);
  return scene;
}

// The message ValidateScene throws for `scene`; "" when it accepts the scene.
std::string ValidationError(const Scene& scene) {
  return ErrorMessage<std::invalid_argument>([&] { ValidateScene(scene); });
}

TEST(SceneValidationTest, AConsistentSceneIsAccepted) {
  EXPECT_EQ(ValidationError(ValidScene()), "");
  EXPECT_EQ(ValidationError(Scene()), "");
}

TEST(SceneValidationTest, TexturesMustHoldTheirSizeInRgba8) {
  Scene scene = ValidScene();
  scene.textures[0].rgba.pop_back();
  EXPECT_EQ(ValidationError(scene), "broken.glb: texture 'bricks' has size 2x2 but 15 bytes (RGBA8 expected)");
  scene = ValidScene();
  scene.textures[0].width = 0;
  scene.textures[0].rgba.clear();
  EXPECT_EQ(ValidationError(scene), "broken.glb: texture 'bricks' has size 0x2 but 0 bytes (RGBA8 expected)");
}

TEST(SceneValidationTest, IndicesMakeWholeTrianglesOfExistingPositions) {
  Scene scene = ValidScene();
  scene.meshes[0].indices.push_back(0);
  EXPECT_EQ(ValidationError(scene), "broken.glb: mesh 0 'quad': index count is not a multiple of 3");
  scene.meshes[0].indices = {0, 1, 7};
  EXPECT_EQ(ValidationError(scene), "broken.glb: mesh 0 'quad': index 7 >= 4 positions");
}

TEST(SceneValidationTest, PerVertexAttributesComeOnePerPosition) {
  struct Case {
    void (*break_mesh)(SceneMesh&);
    std::string message;
  };
  const Case cases[] = {
      {[](SceneMesh& m) { m.normals = {{0, 0, 1}}; }, "1 normals for 4 positions"},
      {[](SceneMesh& m) { m.texcoords.pop_back(); }, "3 texcoords for 4 positions"},
      {[](SceneMesh& m) { m.normal_texcoords = {{0, 0}}; }, "1 normal-map texcoords for 4 positions"},
      {[](SceneMesh& m) { m.emissive_texcoords = {{0, 0}}; }, "1 emissive texcoords for 4 positions"},
      {[](SceneMesh& m) { m.occlusion_texcoords = {{0, 0}}; }, "1 occlusion texcoords for 4 positions"},
      {[](SceneMesh& m) { m.colors = {Eigen::Vector4f::Ones()}; }, "1 vertex colours for 4 positions"},
  };
  for (const Case& c : cases) {
    Scene scene = ValidScene();
    c.break_mesh(scene.meshes[0]);
    EXPECT_EQ(ValidationError(scene), "broken.glb: mesh 0 'quad': " + c.message);
  }
}

TEST(SceneValidationTest, MaterialAndTextureIndicesAreInRange) {
  Scene scene = ValidScene();
  scene.meshes[0].material = 1;
  EXPECT_EQ(ValidationError(scene), "broken.glb: mesh 0 'quad': material index 1 out of range");
  scene.meshes[0].material = -2;
  EXPECT_EQ(ValidationError(scene), "broken.glb: mesh 0 'quad': material index -2 out of range");
  scene = ValidScene();
  scene.materials[0].normal_texture = 3;
  EXPECT_EQ(ValidationError(scene), "broken.glb: mesh 0 'quad': material 'wall' normal texture index 3 out of range");
  // A material no mesh uses is never read, so its indices are not checked.
  scene = ValidScene();
  Material unused;
  unused.occlusion_texture = 9;
  scene.materials.push_back(unused);
  EXPECT_EQ(ValidationError(scene), "");
}

TEST(SceneValidationTest, TheFirstFaultIsReportedTexturesFirst) {
  Scene scene = ValidScene();
  scene.meshes.push_back(scene.meshes[0]);
  scene.meshes[1].name = "second";
  scene.meshes[1].indices = {0, 1, 9};
  EXPECT_EQ(ValidationError(scene), "broken.glb: mesh 1 'second': index 9 >= 4 positions");
  scene.meshes[0].indices = {0, 1};
  EXPECT_EQ(ValidationError(scene), "broken.glb: mesh 0 'quad': index count is not a multiple of 3");
  scene.textures[0].height = 3;
  EXPECT_EQ(ValidationError(scene), "broken.glb: texture 'bricks' has size 2x3 but 16 bytes (RGBA8 expected)");
}

TEST(SceneValidationTest, AnUnnamedSceneIsCalledScene) {
  Scene scene = ValidScene();
  scene.source.clear();
  EXPECT_EQ(SceneName(scene), "scene");
  scene.meshes[0].indices.push_back(0);
  EXPECT_EQ(ValidationError(scene), "scene: mesh 0 'quad': index count is not a multiple of 3");
}

// Posed meshes are checked against the scene's materials and textures.
TEST(SceneValidationTest, OtherMeshesAreCheckedAgainstTheScenesMaterials) {
  const Scene scene = ValidScene();
  std::vector<SceneMesh> posed = scene.meshes;
  EXPECT_NO_THROW(ValidateMeshes(scene, posed));
  posed[0].material = 4;
  EXPECT_THAT([&] { ValidateMeshes(scene, posed); },
              ThrowsExactly<std::invalid_argument>("broken.glb: mesh 0 'quad': material index 4 out of range"));
}

}  // namespace
}  // namespace rigsim
