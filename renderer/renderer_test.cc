// The render loop through Renderer: range, label and instance of every pixel, sky, colours lined
// up with labels, each sample's shadow answer handed back to its own pixel, the same bytes
// whatever the thread count, and checked options and scenes.
#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "labels/cityscapes.h"
#include "renderer/render_test_scenes.h"
#include "renderer/renderer.h"
#include "testing/expect_error.h"

namespace rigsim {
namespace {

TEST(RendererTest, RangeOfFrontoParallelPlane) {
  Scene scene;
  const float d = 5.0f;
  AddFrontQuad(scene, -100, 100, -100, 100, d, kRoad, 1);
  const Renderer renderer(scene);
  // cx, cy on a pixel centre so that one ray is the optical axis; also a distorting lens.
  for (const Camera& camera : {Camera(CameraModelId::kPinhole, 64, 48, {40, 40, 32, 24}),
                               Camera(CameraModelId::kOpenCV, 64, 48, {40, 42, 32, 24, -0.2, 0.03, 0.001, -0.002}),
                               Camera(CameraModelId::kOpenCVFisheye, 64, 48, {35, 35, 32, 24, 0.05, -0.01, 0.002, 0})}) {
    const RenderedView view = renderer.Render(camera, Rigid3d(), Opts());
    EXPECT_NEAR(view.range.at(32, 24), d, 1e-5 * d);
    for (int y = 0; y < 48; ++y) {
      for (int x = 0; x < 64; ++x) {
        const auto bearing = camera.CamFromImg(Eigen::Vector2d(x, y));
        ASSERT_TRUE(bearing.has_value());
        // d / cos(angle to the optical axis)
        ASSERT_NEAR(view.range.at(x, y), d / bearing->normalized().z(), 2e-5 * d) << x << "," << y;
        ASSERT_EQ(view.label.at(x, y), kRoad);
        ASSERT_EQ(view.instance.at(x, y), 1);
      }
    }
  }
}

TEST(RendererTest, SkyAndInstancesPerMesh) {
  Scene scene;
  AddFrontQuad(scene, -2, -0.2f, -1, 1, 4, kCar, 5);
  AddFrontQuad(scene, 0.2f, 2, -1, 1, 6, kRoad, 9);
  const Camera camera = SmallPinhole();
  const RenderedView view = Renderer(scene).Render(camera, Rigid3d(), Opts());
  auto px = [&](double x, double y, double z) {
    const Eigen::Vector2d p = *camera.ImgFromCam(Eigen::Vector3d(x, y, z));
    return std::pair<int, int>(int(std::lround(p.x())), int(std::lround(p.y())));
  };
  const auto [ax, ay] = px(-1.1, 0, 4);
  const auto [bx, by] = px(1.1, 0, 6);
  EXPECT_EQ(view.instance.at(ax, ay), 5);
  EXPECT_EQ(view.label.at(ax, ay), kCar);
  EXPECT_NEAR(view.range.at(ax, ay), Eigen::Vector3d(-1.1, 0, 4).norm(), 0.05);
  EXPECT_EQ(view.instance.at(bx, by), 9);
  EXPECT_EQ(view.label.at(bx, by), kRoad);
  // Nothing behind: sky with no instance and no range, and a sky colour (blue-ish, not black).
  for (const auto& [x, y] : {std::pair{32, 2}, std::pair{31, 24}, std::pair{1, 45}}) {
    EXPECT_EQ(view.label.at(x, y), kSkyId);
    EXPECT_EQ(view.instance.at(x, y), 0);
    EXPECT_EQ(view.range.at(x, y), 0.0f);
    EXPECT_GT(view.rgb.at(x, y, 2), 100);
  }
}

TEST(RendererTest, LabelsLineUpWithColours) {
  Scene scene;
  const int red = AddMaterial(scene, {1, 0, 0, 1});
  const int green = AddMaterial(scene, {0, 1, 0, 1});
  // Textured: a 2x2 texture of red and blue texels, smoothly (bilinearly) filtered.
  const int tex = AddTexture(scene, 2, 2, {{255, 0, 0, 255}, {0, 0, 255, 255}, {0, 0, 255, 255}, {255, 0, 0, 255}},
                             WrapMode::kClampToEdge, false);
  const int textured = AddMaterial(scene, {1, 1, 1, 1}, tex);
  AddFrontQuad(scene, -0.3f, 0.9f, -0.5f, 0.4f, 3, kCar, 1, red);
  AddFrontQuad(scene, -1.5f, -0.6f, -0.5f, 0.6f, 3.5f, 24 /*person*/, 2, textured);
  AddFrontQuad(scene, -50, 50, -50, 50, 8, kRoad, 3, green);
  for (int spp : {1, 4}) {
    RenderOptions options = Opts();
    options.samples_per_pixel = spp;
    const RenderedView view = Renderer(scene).Render(SmallPinhole(), Rigid3d(), options);
    int counts[3] = {0, 0, 0};
    for (int y = 0; y < 48; ++y) {
      for (int x = 0; x < 64; ++x) {
        const uint8_t r = view.rgb.at(x, y, 0), g = view.rgb.at(x, y, 1), b = view.rgb.at(x, y, 2);
        const uint8_t label = view.label.at(x, y);
        // With 1 spp the colour comes from the very ray of the label; with 4 spp only pixels on a
        // boundary may mix colours, so check pixels whose neighbours share the label.
        bool interior = true;
        for (int dy = -1; dy <= 1; ++dy) {
          for (int dx = -1; dx <= 1; ++dx) {
            const int nx = std::clamp(x + dx, 0, 63), ny = std::clamp(y + dy, 0, 47);
            interior &= view.label.at(nx, ny) == label;
          }
        }
        if (spp > 1 && !interior) continue;
        if (label == kCar) {
          ++counts[0];
          ASSERT_GT(r, 20) << x << "," << y;
          ASSERT_EQ(g, 0);
          ASSERT_EQ(b, 0);
        } else if (label == kRoad) {
          ++counts[1];
          ASSERT_EQ(r, 0) << x << "," << y;
          ASSERT_GT(g, 20);
          ASSERT_EQ(b, 0);
        } else {
          ASSERT_EQ(label, 24) << x << "," << y;
          ++counts[2];
          ASSERT_EQ(g, 0) << x << "," << y;
          ASSERT_GT(r + b, 20);
        }
      }
    }
    EXPECT_GT(counts[0], 100);
    EXPECT_GT(counts[1], 100);
    EXPECT_GT(counts[2], 50);
  }
}

// Render traces a batch's shadow rays together and hands each answer back to its own pixel. Rows
// here mix sky and the undersides of bars (no shadow ray) with ground in and out of the bars'
// striped shadow; every pixel whose centre is not on an edge must have its analytic colour, so an
// answer handed to the pixel next door fails at every edge of the shadow.
TEST(RendererTest, EveryPixelGetsItsOwnShadowRay) {
  constexpr uint8_t kPole = 17;
  constexpr float kBarHeight = 1.5f, kBarWidth = 0.6f, kBarPitch = 1.2f, kBarNear = 5, kBarFar = -30;
  Scene scene;
  const int grey = AddMaterial(scene, {0.5f, 0.5f, 0.5f, 1});
  AddQuad(scene, {-100, 0, -100}, {100, 0, -100}, {100, 0, 100}, {-100, 0, 100}, kRoad, 1, grey);
  std::vector<float> bar_x;
  for (int i = 0; i <= 10; ++i) {
    const float x0 = -6 + kBarPitch * i;
    bar_x.push_back(x0);
    AddQuad(scene, {x0, kBarHeight, kBarFar}, {x0 + kBarWidth, kBarHeight, kBarFar}, {x0 + kBarWidth, kBarHeight, kBarNear},
            {x0, kBarHeight, kBarNear}, kPole, uint16_t(2 + i), grey);
  }
  RenderOptions options = Opts();
  options.sun_direction_world = Eigen::Vector3d(0.45, 0.85, -0.2);
  const Eigen::Vector3d sun = options.sun_direction_world.normalized();

  // 1 m above the ground looking along -Z, rolled by 25 degrees so that the horizon crosses rows.
  const Eigen::Vector3d centre(0, 1, 6);
  Eigen::Matrix3d level;
  level << Eigen::Vector3d(1, 0, 0), Eigen::Vector3d(0, -1, 0), Eigen::Vector3d(0, 0, -1);
  const Eigen::Matrix3d world_from_cam = level * Eigen::AngleAxisd(25 * M_PI / 180, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const Rigid3d cam_from_world = Rigid3d(world_from_cam, centre).Inverse();
  const Camera camera(CameraModelId::kPinhole, 96, 64, {60, 60, 47.5, 31.5});
  const RenderedView view = Renderer(scene).Render(camera, cam_from_world, options);

  enum Kind { kSky, kBar, kLit, kShadow };
  auto under_bar = [&](const Eigen::Vector3d& p) {  // p at bar height
    if (p.z() < kBarFar || p.z() > kBarNear) return false;
    return std::any_of(bar_x.begin(), bar_x.end(), [&](float x0) { return p.x() >= x0 && p.x() <= x0 + kBarWidth; });
  };
  auto kind_at = [&](double x, double y) {
    const Eigen::Vector3d d = world_from_cam * camera.CamFromImg(Eigen::Vector2d(x, y))->normalized();
    if (d.y() > 0) return under_bar(centre + (kBarHeight - centre.y()) / d.y() * d) ? kBar : kSky;
    if (d.y() == 0) return kSky;
    const Eigen::Vector3d p = centre - centre.y() / d.y() * d;
    if (std::abs(p.x()) > 100 || std::abs(p.z()) > 100) return kSky;
    return under_bar(p + kBarHeight / sun.y() * sun) ? kShadow : kLit;
  };
  auto linear = [](int v) { const double c = v / 255.0; return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4); };
  const double sky = options.sky_intensity;
  const std::array<double, 4> expected = {0, 0.5 * 0.3 * sky, 0.5 * (sky + options.sun_intensity * sun.y()), 0.5 * sky};
  const std::array<uint8_t, 4> label = {kSkyId, kPole, kRoad, kRoad};

  std::array<int, 4> checked{};
  int mixed_rows = 0;  // rows where pixels without a shadow ray sit beside lit and shadowed ground
  for (int y = 1; y + 1 < camera.height(); ++y) {
    std::array<int, 4> in_row{};
    for (int x = 1; x + 1 < camera.width(); ++x) {
      const Kind kind = kind_at(x, y);
      constexpr double kMargin = 0.1;  // px: float rays cannot settle a centre closer to an edge
      if (kind != kind_at(x - kMargin, y) || kind != kind_at(x + kMargin, y) || kind != kind_at(x, y - kMargin) ||
          kind != kind_at(x, y + kMargin)) {
        continue;
      }
      ++checked[kind];
      ++in_row[kind];
      ASSERT_EQ(view.label.at(x, y), label[kind]) << "pixel (" << x << ", " << y << ")";
      if (kind != kSky) {
        EXPECT_NEAR(linear(view.rgb.at(x, y, 0)), expected[kind], 0.01) << "pixel (" << x << ", " << y << ")";
      }
    }
    if (in_row[kSky] + in_row[kBar] > 0 && in_row[kLit] > 0 && in_row[kShadow] > 0) ++mixed_rows;
  }
  for (int kind = 0; kind < 4; ++kind) EXPECT_GT(checked[kind], 100) << "kind " << kind;
  EXPECT_GE(mixed_rows, 10);
}

// cam_from_world of a camera at `centre` looking at `target`, image-up towards world +Y.
Rigid3d LookAt(const Eigen::Vector3d& centre, const Eigen::Vector3d& target) {
  const Eigen::Vector3d z = (target - centre).normalized();
  const Eigen::Vector3d x = Eigen::Vector3d(0, -1, 0).cross(z).normalized();
  Eigen::Matrix3d world_from_cam;
  world_from_cam << x, z.cross(x), z;
  return Rigid3d(world_from_cam, centre).Inverse();
}

RenderedView RenderBusyScene(int threads, int spp, uint64_t seed) {
  Scene scene;
  std::vector<std::array<uint8_t, 4>> checker;
  for (int y = 0; y < 16; ++y) {
    for (int x = 0; x < 16; ++x) checker.push_back({uint8_t(16 * x), uint8_t(255 - 16 * y), 90, 255});
  }
  const int tex = AddMaterial(scene, {1, 1, 1, 1}, AddTexture(scene, 16, 16, checker, WrapMode::kRepeat, false));
  AddQuad(scene, {-20, 0, -20}, {20, 0, -20}, {20, 0, 20}, {-20, 0, 20}, kRoad, 1, tex, 8, 8);
  AddQuad(scene, {-1, 2, -1}, {1, 2.5f, -1}, {1, 2.5f, 1}, {-1, 2, 1}, kCar, 2, AddMaterial(scene, {0.8f, 0.1f, 0.1f, 1}));
  AddQuad(scene, {2, 0, 2}, {3, 0, 2}, {3, 3, 2}, {2, 3, 2}, 20, 3, -1);
  RenderOptions options;
  options.num_threads = threads;
  options.samples_per_pixel = spp;
  options.seed = seed;
  const Rigid3d posed = LookAt(Eigen::Vector3d(1, 5, -6), Eigen::Vector3d(0.5, 0, 0.5));
  // 70 x 50: tiles of 32 do not divide the image.
  const Camera camera(CameraModelId::kOpenCV, 70, 50, {45, 45, 34.5, 24.5, -0.1, 0.01, 0, 0});
  return Renderer(scene).Render(camera, posed, options);
}

void ExpectSameBytes(const RenderedView& a, const RenderedView& b) {
  EXPECT_EQ(a.rgb.data, b.rgb.data);
  EXPECT_EQ(a.label.data, b.label.data);
  EXPECT_EQ(a.instance.data, b.instance.data);
  EXPECT_EQ(a.range.data, b.range.data);
}

TEST(RendererTest, SameBytesWhateverTheThreadCount) {
  for (int spp : {4, 3}) {  // stratified grid and n-rooks
    const RenderedView one = RenderBusyScene(1, spp, 7);
    ExpectSameBytes(one, RenderBusyScene(2, spp, 7));
    ExpectSameBytes(one, RenderBusyScene(0, spp, 7));
    // The scene is not trivially empty.
    EXPECT_NE(std::count(one.label.data.begin(), one.label.data.end(), kCar), 0);
    EXPECT_NE(std::count(one.label.data.begin(), one.label.data.end(), kRoad), 0);
  }
}

TEST(RendererTest, SeedChangesOnlyTheSampleNoise) {
  const RenderedView a = RenderBusyScene(0, 4, 1);
  const RenderedView b = RenderBusyScene(0, 4, 2);
  // Label, instance and range come from the pixel centre: never from the jitter.
  EXPECT_EQ(a.label.data, b.label.data);
  EXPECT_EQ(a.instance.data, b.instance.data);
  EXPECT_EQ(a.range.data, b.range.data);
  // Differences only where the samples can see different things (edges, texture variation).
  int differing = 0;
  for (size_t i = 0; i < a.rgb.data.size(); ++i) {
    differing += a.rgb.data[i] != b.rgb.data[i];
  }
  EXPECT_GT(differing, 0);
  // Where all four samples see one flat colour (the untextured, evenly lit car roof away from
  // its border), the seed makes no difference.
  for (int y = 0; y < 50; ++y) {
    for (int x = 0; x < 70; ++x) {
      bool flat = true;
      const uint8_t label = a.label.at(x, y);
      for (int dy = -1; dy <= 1; ++dy) {
        for (int dx = -1; dx <= 1; ++dx) {
          const int nx = std::clamp(x + dx, 0, 69), ny = std::clamp(y + dy, 0, 49);
          flat &= a.label.at(nx, ny) == label;
        }
      }
      if (flat && label == kCar) {
        for (int c = 0; c < 3; ++c) EXPECT_EQ(a.rgb.at(x, y, c), b.rgb.at(x, y, c)) << x << "," << y;
      }
    }
  }
}

TEST(RendererTest, OptionsAndSceneAreChecked) {
  RenderOptions options;
  EXPECT_NO_THROW(options.Check());
  options.samples_per_pixel = 0;
  EXPECT_THROW(options.Check(), std::invalid_argument);
  options = RenderOptions();
  options.sun_direction_world = Eigen::Vector3d::Zero();
  EXPECT_THROW(options.Check(), std::invalid_argument);
  options = RenderOptions();
  options.num_threads = -1;
  EXPECT_THROW(options.Check(), std::invalid_argument);

  Scene scene;
  scene.source = "broken.glb";
  AddFrontQuad(scene, -1, 1, -1, 1, 3, kCar, 1);
  scene.meshes[0].indices.push_back(0);
  EXPECT_THROW(Renderer{scene}, std::invalid_argument);
  scene.meshes[0].indices = {0, 1, 7};
  EXPECT_THAT([&] { Renderer renderer(scene); }, ThrowsWith<std::invalid_argument>("broken.glb"));
  scene.meshes[0].indices = {0, 1, 2};
  scene.meshes[0].colors = {Eigen::Vector4f::Ones()};  // one colour for four vertices
  EXPECT_THAT([&] { Renderer renderer(scene); }, ThrowsWith<std::invalid_argument>("1 vertex colours for 4 positions"));
}

TEST(RendererTest, EmptySceneIsAllSky) {
  const RenderedView view = Renderer(Scene()).Render(SmallPinhole(), Rigid3d(), Opts());
  for (uint8_t label : view.label.data) ASSERT_EQ(label, kSkyId);
  for (float r : view.range.data) ASSERT_EQ(r, 0.0f);
}

}  // namespace
}  // namespace rigsim
