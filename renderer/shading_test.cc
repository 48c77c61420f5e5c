// Shading, seen in rendered colours: vertex colours, unlit and emissive materials, normal and
// occlusion maps, sun light and hard shadows.
#include <array>
#include <cmath>
#include <stdexcept>

#include <gtest/gtest.h>

#include "renderer/render_test_scenes.h"
#include "renderer/renderer.h"
#include "renderer/srgb.h"

namespace rigsim {
namespace {

// COLOR_0 (glTF 2.0) multiplies the base colour factor, is interpolated across the triangles, and
// its alpha takes part in the MASK test; without a material the colours show as they are.
TEST(ShadingTest, VertexColoursMultiplyTheBaseColourAndTheirAlphaCutsOut) {
  const Camera camera = SmallPinhole();
  // Corners at x = -1 red, at x = 1 blue; `factor` < 0: no material.
  auto render = [&](const Eigen::Vector4f& factor, const Eigen::Vector4f& red) {
    Scene scene;
    const int material = factor[0] < 0 ? -1 : AddMaterial(scene, factor);
    const int quad = AddFrontQuad(scene, -1, 1, -1, 1, 3, kCar, 1, material);
    const Eigen::Vector4f blue(0, 0, 1, 1);
    scene.meshes[quad].colors = {red, blue, blue, red};
    return Renderer(scene).Render(camera, Rigid3d(), Opts());
  };
  const Eigen::Vector4f red(1, 0, 0, 1);
  const RenderedView view = render({1, 1, 1, 1}, red);
  // Linear red / blue at x: (1 - x) / (1 + x), no green.
  for (const double x : {-0.5, 0.0, 0.5}) {
    const std::array<int, 3> c = ColourAt(view, camera, {x, 0, 3});
    EXPECT_EQ(c[1], 0);
    EXPECT_NEAR(LinearFromSrgbCode(uint8_t(c[0])) / LinearFromSrgbCode(uint8_t(c[2])), (1 - x) / (1 + x), 0.1 * (1 - x) / (1 + x))
        << "x = " << x;
  }
  // No material: glTF's default is white, so the colours are not darkened by the default grey.
  EXPECT_EQ(render({-1, 0, 0, 0}, red).rgb.data, view.rgb.data);
  // The factor and the colour multiply: a factor of 0.5 in red on red corners is red corners of 0.5.
  EXPECT_EQ(render({0.5f, 1, 1, 1}, red).rgb.data, render({1, 1, 1, 1}, {0.5f, 0, 0, 1}).rgb.data);
  EXPECT_NE(render({0.5f, 1, 1, 1}, red).rgb.data, view.rgb.data);

  // Alpha 0 at x = -1 and 1 at x = 1 under MASK (cutoff 0.5): the left half is cut out.
  Scene scene;
  const int mask = AddMaterial(scene, {1, 1, 1, 1});
  scene.materials[mask].alpha_mode = AlphaMode::kMask;
  scene.materials[mask].alpha_cutoff = 0.5f;
  const int quad = AddFrontQuad(scene, -1, 1, -1, 1, 3, kCar, 4, mask);
  scene.meshes[quad].colors = {{1, 1, 1, 0}, {1, 1, 1, 1}, {1, 1, 1, 1}, {1, 1, 1, 0}};
  AddFrontQuad(scene, -50, 50, -50, 50, 6, kRoad, 7);
  const RenderedView masked = Renderer(scene).Render(camera, Rigid3d(), Opts());
  const Eigen::Vector2d left = *camera.ImgFromCam(Eigen::Vector3d(-0.5, 0, 3));
  const Eigen::Vector2d right = *camera.ImgFromCam(Eigen::Vector3d(0.5, 0, 3));
  const int y = int(std::lround(left.y()));
  EXPECT_EQ(masked.label.at(int(std::lround(left.x())), y), kRoad);
  EXPECT_EQ(masked.label.at(int(std::lround(right.x())), y), kCar);
}

// KHR_materials_unlit: the base colour is the pixel's linear value, whatever the sun, the sky, the
// surface's orientation or a shadow; the same material lit is shaded.
TEST(ShadingTest, UnlitMaterialsShowTheirBaseColour) {
  for (const bool unlit : {true, false}) {
    Scene scene;
    const int grey = AddMaterial(scene, {0.5f, 0.25f, 0.125f, 1});
    scene.materials[grey].unlit = unlit;
    AddFrontQuad(scene, -1, 1, -1, 1, 3, kCar, 1, grey);
    // An occluder between the quad and the sun (which shines from behind the camera, above).
    AddQuad(scene, {-3, -4, 0}, {3, -4, 0}, {3, -4, 6}, {-3, -4, 6}, kRoad, 2);
    RenderOptions options = Opts();
    options.sun_direction_world = Eigen::Vector3d(0, -1, -0.3);
    const Camera camera = SmallPinhole();
    const RenderedView view = Renderer(scene).Render(camera, Rigid3d(), options);
    const std::array<int, 3> c = ColourAt(view, camera, {0, 0, 3});
    const std::array<int, 3> expected = {SrgbCodeFromLinear(0.5f), SrgbCodeFromLinear(0.25f), SrgbCodeFromLinear(0.125f)};
    if (unlit) {
      EXPECT_EQ(c, expected);
    } else {
      EXPECT_NE(c, expected);
    }
  }
}

// Emission adds to the reflected light, in shadow too, and is the colour itself on a black
// surface; an unlit material ignores it.
TEST(ShadingTest, EmissionAddsToTheReflectedLight) {
  const Eigen::Vector3f emission(0.25f, 0.125f, 0.0f);
  auto render = [&](const Eigen::Vector4f& base, const Eigen::Vector3f& emissive, bool unlit) {
    Scene scene;
    const int material = AddMaterial(scene, base);
    scene.materials[material].emissive = emissive;
    scene.materials[material].unlit = unlit;
    AddFrontQuad(scene, -1, 1, -1, 1, 3, kCar, 1, material);
    AddQuad(scene, {-3, -4, 0}, {3, -4, 0}, {3, -4, 6}, {-3, -4, 6}, kRoad, 2);  // shades the quad from the sun
    RenderOptions options = Opts();
    options.sun_direction_world = Eigen::Vector3d(0, -1, -0.3);
    const Camera camera = SmallPinhole();
    return ColourAt(Renderer(scene).Render(camera, Rigid3d(), options), camera, {0, 0, 3});
  };
  auto linear = [](int code) { return LinearFromSrgbCode(uint8_t(code)); };
  const Eigen::Vector4f grey(0.5f, 0.5f, 0.5f, 1);
  const std::array<int, 3> dark = render(grey, Eigen::Vector3f::Zero(), false);
  const std::array<int, 3> glowing = render(grey, emission, false);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(linear(glowing[c]) - linear(dark[c]), emission[c], 0.005) << c;
  const std::array<int, 3> black = render({0, 0, 0, 1}, emission, false);
  for (int c = 0; c < 3; ++c) EXPECT_EQ(black[c], SrgbCodeFromLinear(emission[c])) << c;
  EXPECT_EQ(render(grey, emission, true), render(grey, Eigen::Vector3f::Zero(), true));
}

// The emissive texture multiplies the emission and is read through its own coordinates: here u
// runs the other way from the base colour's, so the red | blue texture shows blue | red.
TEST(ShadingTest, EmissiveTextureUsesItsOwnTexcoords) {
  Scene scene;
  const int tex = AddTexture(scene, 2, 1, {{255, 0, 0, 255}, {0, 0, 255, 255}});
  const int material = AddMaterial(scene, {0, 0, 0, 1}, tex);  // black: the texture shows only as emission
  scene.materials[material].emissive = Eigen::Vector3f(1, 1, 1);
  scene.materials[material].emissive_texture = tex;
  AddFrontQuad(scene, -1, 1, -1, 1, 3, kCar, 1, material);
  scene.meshes.back().emissive_texcoords = {{1, 0}, {0, 0}, {0, 1}, {1, 1}};
  const Camera camera = SmallPinhole();
  const Renderer renderer(scene);
  const RenderedView view = renderer.Render(camera, Rigid3d(), Opts());
  EXPECT_EQ(ColourAt(view, camera, {-0.5, 0, 3}), (std::array<int, 3>{0, 0, 255}));
  EXPECT_EQ(ColourAt(view, camera, {0.5, 0, 3}), (std::array<int, 3>{255, 0, 0}));

  scene.meshes.back().emissive_texcoords.pop_back();
  EXPECT_THROW(Renderer{scene}, std::invalid_argument) << "emissive texcoords must match the positions";
}

// Red channel of the pixel at the centre of a white 2 x 2 m quad 3 m ahead whose normal map is
// the single texel `normal` (RGB codes). `facing_camera`: the quad's outside (winding) faces the
// camera, with u growing to the image's left and v downwards; else the camera sees its back.
int NormalMappedRed(const std::array<uint8_t, 3>& normal, bool facing_camera, const Eigen::Vector3d& sun) {
  Scene scene;
  const int map = AddTexture(scene, 1, 1, {{normal[0], normal[1], normal[2], 255}});
  const int material = AddMaterial(scene, {1, 1, 1, 1});
  scene.materials[material].normal_texture = map;
  AddFrontQuad(scene, facing_camera ? 1 : -1, facing_camera ? -1 : 1, -1, 1, 3, kCar, 1, material);
  scene.meshes.back().normal_texcoords = scene.meshes.back().texcoords;
  RenderOptions options = Opts();
  options.sun_direction_world = sun;
  const Camera camera = SmallPinhole();
  return ColourAt(Renderer(scene).Render(camera, Rigid3d(), options), camera, {0, 0, 3})[0];
}

// The normal map turns the shading normal: +X along u, +Y towards the texture's top row (the
// image's top here, world -y), +Z out of the surface; seen from the back the frame turns over.
TEST(ShadingTest, NormalMapsTurnTheShadingNormal) {
  const std::array<uint8_t, 3> flat = {128, 128, 255}, up = {128, 255, 128}, down = {128, 0, 128};
  const std::array<uint8_t, 3> along_u = {255, 128, 128}, against_u = {0, 128, 128};
  const Eigen::Vector3d sun_above(0, -1, -0.2), sun_left(-1, 0, -0.2);  // left: where u grows
  const int flat_above = NormalMappedRed(flat, true, sun_above);
  EXPECT_GT(NormalMappedRed(up, true, sun_above), flat_above + 40);
  EXPECT_LT(NormalMappedRed(down, true, sun_above), flat_above);
  const int flat_left = NormalMappedRed(flat, true, sun_left);
  EXPECT_GT(NormalMappedRed(along_u, true, sun_left), flat_left + 40);
  EXPECT_LT(NormalMappedRed(against_u, true, sun_left), flat_left);
  // From the back, "up" on the map points away from the sun above.
  EXPECT_LT(NormalMappedRed(up, false, sun_above), NormalMappedRed(flat, false, sun_above));
  // A flat map changes (almost) nothing: 128 is a hair above the middle of 0..255.
  Scene plain;
  AddFrontQuad(plain, 1, -1, -1, 1, 3, kCar, 1, AddMaterial(plain, {1, 1, 1, 1}));
  RenderOptions options = Opts();
  options.sun_direction_world = sun_above;
  const Camera camera = SmallPinhole();
  EXPECT_NEAR(ColourAt(Renderer(plain).Render(camera, Rigid3d(), options), camera, {0, 0, 3})[0], flat_above, 1);
}

// The occlusion map scales the sky light by 1 + strength * (occlusion - 1), read from its red
// channel as data (not sRGB), and leaves the sun alone.
TEST(ShadingTest, OcclusionScalesTheSkyLightOnly) {
  auto linear_red = [](uint8_t code, float strength, bool sun) {
    Scene scene;
    const int map = AddTexture(scene, 1, 1, {{code, 255, 255, 255}});
    const int material = AddMaterial(scene, {1, 1, 1, 1});
    scene.materials[material].occlusion_texture = map;
    scene.materials[material].occlusion_strength = strength;
    AddFrontQuad(scene, 1, -1, -1, 1, 3, kCar, 1, material);
    scene.meshes.back().occlusion_texcoords = scene.meshes.back().texcoords;
    RenderOptions options = Opts();
    options.sun_direction_world = Eigen::Vector3d(0, 0, -1);  // straight at the quad's lit side
    options.sun_intensity = sun ? 0.4 : 0.0;  // below white, so nothing clips
    const Camera camera = SmallPinhole();
    const int v = ColourAt(Renderer(scene).Render(camera, Rigid3d(), options), camera, {0, 0, 3})[0];
    const double c = v / 255.0;
    return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4);
  };
  const double open = linear_red(255, 1, false);
  EXPECT_NEAR(linear_red(51, 1, false), 0.2 * open, 0.005);            // code 51 = 0.2 as data
  EXPECT_NEAR(linear_red(51, 0.5f, false), 0.6 * open, 0.005);         // 1 + 0.5 (0.2 - 1)
  EXPECT_NEAR(linear_red(0, 0, false), open, 0.005);                   // strength 0: no effect
  const double sun_only = linear_red(255, 1, true) - open;
  EXPECT_NEAR(linear_red(0, 1, true), sun_only, 0.01);                 // fully occluded: the sun alone
}

// A camera 10 m above the origin looking straight down (+Z of the world at the image bottom).
Rigid3d LookingDown(double height) {
  Eigen::Matrix3d world_from_cam;
  world_from_cam.col(0) = Eigen::Vector3d(1, 0, 0);
  world_from_cam.col(1) = Eigen::Vector3d(0, 0, 1);
  world_from_cam.col(2) = Eigen::Vector3d(0, -1, 0);
  return Rigid3d(world_from_cam, Eigen::Vector3d(0, height, 0)).Inverse();
}

TEST(ShadingTest, SunLightAndHardShadows) {
  Scene scene;
  const int grey = AddMaterial(scene, {0.5f, 0.5f, 0.5f, 1});
  // Ground (y = 0, facing up) and a 1 m square 4 m above it.
  AddQuad(scene, {-50, 0, -50}, {50, 0, -50}, {50, 0, 50}, {-50, 0, 50}, kRoad, 1, grey);
  AddQuad(scene, {-0.5f, 4, -0.5f}, {0.5f, 4, -0.5f}, {0.5f, 4, 0.5f}, {-0.5f, 4, 0.5f}, kCar, 2, grey);
  RenderOptions options = Opts();
  options.sun_direction_world = Eigen::Vector3d(0.4, 0.8, 0.3);
  const Eigen::Vector3d sun = options.sun_direction_world.normalized();
  const Camera camera(CameraModelId::kPinhole, 64, 48, {80, 80, 31.5, 23.5});
  const Rigid3d cam_from_world = LookingDown(10);
  const Renderer renderer(scene);
  const RenderedView view = renderer.Render(camera, cam_from_world, options);

  const Eigen::Vector3d shadow_centre = Eigen::Vector3d(0, 4, 0) - sun * (4 / sun.y());
  const Eigen::Vector3d lit_ground = -shadow_centre;
  const Eigen::Vector2d ps = *camera.ImgFromCam(cam_from_world * shadow_centre);
  const Eigen::Vector2d pl = *camera.ImgFromCam(cam_from_world * lit_ground);
  const int sx = int(std::lround(ps.x())), sy = int(std::lround(ps.y()));
  const int lx = int(std::lround(pl.x())), ly = int(std::lround(pl.y()));
  ASSERT_EQ(view.label.at(sx, sy), kRoad);
  ASSERT_EQ(view.label.at(lx, ly), kRoad);
  EXPECT_NEAR(view.range.at(sx, sy), 10 / camera.CamFromImg(Eigen::Vector2d(sx, sy))->normalized().z(), 1e-4);
  // Shadowed: ambient only (0.5 * sky), lit: + 0.5 * sun * cos.
  auto linear = [](int v) { const double c = v / 255.0; return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4); };
  EXPECT_NEAR(linear(view.rgb.at(sx, sy, 0)), 0.5 * options.sky_intensity, 0.01);
  EXPECT_NEAR(linear(view.rgb.at(lx, ly, 0)), 0.5 * (options.sky_intensity + options.sun_intensity * sun.y()), 0.01);

  options.shadows = false;
  const RenderedView unshadowed = renderer.Render(camera, cam_from_world, options);
  EXPECT_EQ(unshadowed.rgb.at(sx, sy, 0), view.rgb.at(lx, ly, 0));
}

}  // namespace
}  // namespace rigsim
