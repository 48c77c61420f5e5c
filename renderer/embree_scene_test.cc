// The Embree scene, seen in rendered outputs: watertight traversal through shared edges, and alpha
// MASK cutting geometry out of every output.
#include <cmath>

#include <gtest/gtest.h>

#include "renderer/embree_scene.h"
#include "renderer/render_test_scenes.h"
#include "renderer/renderer.h"

namespace rigsim {
namespace {

// Embree's 8-wide kernels render other bytes than its SSE ones (AVX2: other depths and colours;
// AVX: another instance where a ray meets two surfaces at one distance), so on a CPU that has them
// this fails if the renderer stops holding Embree to SSE2. Embree's own report of the device's
// native ray packets says which kernels it chose.
TEST(EmbreeSceneTest, EmbreeRunsItsSse2KernelsWhateverTheCpu) {
  const EmbreeScene scene("test");
  EXPECT_FALSE(scene.UsesWideKernels());
}

// Rays through the edge two triangles share hit one of them: no crack lets the backdrop show
// through. Every quad of the grid is split along a diagonal that passes exactly through pixel
// centres, as in a glTF file with six such quads that showed 13 cracked pixels. The camera looks
// down -Z as a glTF camera does.
TEST(EmbreeSceneTest, RaysThroughASharedEdgeDoNotSeeThrough) {
  Scene scene;
  for (int i = -5; i < 5; ++i) {
    for (int j = -4; j < 4; ++j) {
      const int quad = AddFrontQuad(scene, float(i), float(i + 1), float(j), float(j + 1), -5.0f, kRoad, 1);
      scene.meshes[quad].indices = {0, 1, 3, 1, 2, 3};  // the diagonal from (i + 1, j) to (i, j + 1)
    }
  }
  AddFrontQuad(scene, -100, 100, -100, 100, -9.0f, kCar, 2);
  const Renderer renderer(scene);
  const Camera camera(CameraModelId::kPinhole, 320, 240, {160, 160, 159.5, 119.5});
  const Rigid3d looking_down_minus_z(Eigen::Quaterniond(0, 1, 0, 0), Eigen::Vector3d::Zero());
  const RenderedView view = renderer.Render(camera, looking_down_minus_z, Opts());
  int seen_through = 0;
  for (int y = 0; y < 240; ++y) {
    for (int x = 0; x < 320; ++x) seen_through += view.label.at(x, y) != kRoad || view.instance.at(x, y) != 1;
  }
  EXPECT_EQ(seen_through, 0);
}

TEST(EmbreeSceneTest, AlphaMaskCutsOutGeometryInEveryOutput) {
  Scene scene;
  // Left texel transparent, right texel opaque.
  const int tex = AddTexture(scene, 2, 1, {{255, 0, 0, 0}, {255, 0, 0, 255}}, WrapMode::kClampToEdge, true);
  const int mat = AddMaterial(scene, {1, 1, 1, 1}, tex);
  scene.materials[mat].alpha_mode = AlphaMode::kMask;
  scene.materials[mat].alpha_cutoff = 0.5f;
  AddFrontQuad(scene, -1, 1, -1, 1, 3, kCar, 4, mat);
  AddFrontQuad(scene, -50, 50, -50, 50, 6, kRoad, 7, AddMaterial(scene, {0, 1, 0, 1}));
  const Camera camera = SmallPinhole();
  const RenderedView view = Renderer(scene).Render(camera, Rigid3d(), Opts());
  const Eigen::Vector2d left = *camera.ImgFromCam(Eigen::Vector3d(-0.5, 0, 3));
  const Eigen::Vector2d right = *camera.ImgFromCam(Eigen::Vector3d(0.5, 0, 3));
  const int lx = int(std::lround(left.x())), rx = int(std::lround(right.x())), y = int(std::lround(left.y()));
  EXPECT_EQ(view.label.at(lx, y), kRoad);
  EXPECT_EQ(view.instance.at(lx, y), 7);
  EXPECT_NEAR(view.range.at(lx, y), 6 / camera.CamFromImg(Eigen::Vector2d(lx, y))->normalized().z(), 1e-4);
  EXPECT_EQ(view.rgb.at(lx, y, 0), 0);
  EXPECT_GT(view.rgb.at(lx, y, 1), 20);
  EXPECT_EQ(view.label.at(rx, y), kCar);
  EXPECT_EQ(view.instance.at(rx, y), 4);
  EXPECT_NEAR(view.range.at(rx, y), 3 / camera.CamFromImg(Eigen::Vector2d(rx, y))->normalized().z(), 1e-4);
  EXPECT_GT(view.rgb.at(rx, y, 0), 20);
}

}  // namespace
}  // namespace rigsim
