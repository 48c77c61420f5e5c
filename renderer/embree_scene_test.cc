// The Embree scene, seen in rendered outputs: watertight traversal through shared edges, and alpha
// MASK cutting geometry out of every output.
#include <array>
#include <cmath>
#include <random>

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

// Where the ray from `org` along `dir` meets the triangle (a, b, c): Moller-Trumbore in double
// precision, rounded to float, written out here independently of the renderer.
std::array<float, 3> ExactTUV(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
                              const Eigen::Vector3d& org, const Eigen::Vector3d& dir) {
  const Eigen::Vector3d e1 = b - a, e2 = c - a, p = dir.cross(e2), s = org - a, q = s.cross(e1);
  const double det = e1.dot(p);
  return {float(e2.dot(q) / det), float(s.dot(p) / det), float(dir.dot(q) / det)};
}

// A hit's distance and barycentrics are the exact ones rounded to float, not Embree's, which come
// from approximate reciprocals (RCPPS) whose last bits differ between Intel's and AMD's CPUs
// (bench/cpu_vendor_check.sh): for a still triangle and for one moving between two time steps.
TEST(EmbreeSceneTest, HitDistancesAndBarycentricsAreExactOnEveryCpu) {
  SceneMesh still;
  still.positions = {{-3.1f, -2.3f, -7.7f}, {4.3f, -1.9f, -6.1f}, {0.7f, 3.9f, -8.3f}};
  still.indices = {0, 1, 2};
  SceneMesh moved = still;
  for (Eigen::Vector3f& p : moved.positions) p += Eigen::Vector3f(0.37f, -0.11f, 0.53f);
  const std::vector<std::vector<SceneMesh>> steps = {{still}, {moved}};
  const std::vector<MeshShading> shading(1);
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> spread(-0.3f, 0.3f), when(0.f, 1.f);
  for (const bool moving : {false, true}) {
    EmbreeScene scene("test");
    scene.Build({still}, shading, moving ? &steps : nullptr);
    std::vector<RTCRayHit> rays;
    for (int i = 0; i < 500; ++i) {
      RTCRayHit rh = CameraRay(Eigen::Vector3f(0.1f, 0.2f, 0.3f), Eigen::Vector3f(spread(rng), spread(rng), -1.f).normalized());
      rh.ray.time = moving ? when(rng) : 0.f;
      rays.push_back(rh);
    }
    scene.Intersect(rays);
    int hits = 0;
    for (const RTCRayHit& rh : rays) {
      if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) continue;
      ++hits;
      const double w = rh.ray.time;
      Eigen::Vector3d corner[3];
      for (int k = 0; k < 3; ++k) {
        corner[k] = (1 - w) * still.positions[k].cast<double>() + w * (moving ? moved : still).positions[k].cast<double>();
      }
      const std::array<float, 3> tuv =
          ExactTUV(corner[0], corner[1], corner[2], Eigen::Vector3d(rh.ray.org_x, rh.ray.org_y, rh.ray.org_z),
                   Eigen::Vector3d(rh.ray.dir_x, rh.ray.dir_y, rh.ray.dir_z));
      ASSERT_EQ(rh.ray.tfar, tuv[0]) << (moving ? "moving" : "still") << ", time " << w;
      ASSERT_EQ(rh.hit.u, tuv[1]);
      ASSERT_EQ(rh.hit.v, tuv[2]);
    }
    EXPECT_GT(hits, 300) << (moving ? "moving" : "still");
  }
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
