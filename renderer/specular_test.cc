// One specular bounce: a mirror shows a known scene point where the law of reflection puts it,
// rough surfaces show none, the ground truth stays the mirror's, and a moving target is reflected
// where it is at the camera ray's time.
#include <array>
#include <cmath>
#include <vector>

#include <Eigen/Core>
#include <gtest/gtest.h>

#include "renderer/render_test_scenes.h"
#include "renderer/renderer.h"
#include "renderer/shading.h"

namespace rigsim {
namespace {

constexpr uint16_t kMirrorId = 1, kTargetId = 2;
constexpr float kMirrorY = 1.0f;  // the mirror is the plane y = 1 of the camera frame (identity pose)
const Eigen::Vector3d kTarget(0.3, -0.5, 8.0);  // the target's centre, in front of the camera, above the mirror

// A mirror plane y = kMirrorY for z in [1, 30] and a small unlit red square facing the camera,
// centred at (target_x, kTarget.y, kTarget.z).
Scene MirrorScene(float roughness, float metallic, float target_x = float(kTarget.x())) {
  Scene scene;
  const int mirror = AddMaterial(scene, Eigen::Vector4f(1, 1, 1, 1));
  scene.materials[mirror].roughness = roughness;
  scene.materials[mirror].metallic = metallic;
  const int red = AddMaterial(scene, Eigen::Vector4f(1, 0, 0, 1));
  scene.materials[red].unlit = true;
  AddQuad(scene, {-5, kMirrorY, 1}, {5, kMirrorY, 1}, {5, kMirrorY, 30}, {-5, kMirrorY, 30}, kRoad, kMirrorId, mirror);
  const float h = 0.3f, y = float(kTarget.y()), z = float(kTarget.z());
  AddFrontQuad(scene, target_x - h, target_x + h, y - h, y + h, z, kCar, kTargetId, red);
  return scene;
}

// The target's image in the mirror: the point mirrored about the plane, then projected.
Eigen::Vector3d MirrorImage(const Eigen::Vector3d& p) { return {p.x(), 2.0 * kMirrorY - p.y(), p.z()}; }

Eigen::Vector2i PixelOf(const Camera& camera, const Eigen::Vector3d& p) {
  const Eigen::Vector2d px = *camera.ImgFromCam(p);
  return {int(std::lround(px.x())), int(std::lround(px.y()))};
}

std::array<int, 3> Rgb(const RenderedView& view, const Eigen::Vector2i& px) {
  return {view.rgb.at(px.x(), px.y(), 0), view.rgb.at(px.x(), px.y(), 1), view.rgb.at(px.x(), px.y(), 2)};
}

TEST(SpecularTest, GlossOfFollowsRoughnessBelowTheThreshold) {
  Material m;
  EXPECT_EQ(GlossOf(m), 0.0f);  // glTF's default roughness 1
  m.roughness = kGlossyRoughness;
  EXPECT_EQ(GlossOf(m), 0.0f);
  m.roughness = 0.0f;
  EXPECT_EQ(GlossOf(m), 1.0f);
  m.roughness = kGlossyRoughness / 2;
  EXPECT_FLOAT_EQ(GlossOf(m), 0.5f);
  m.unlit = true;
  EXPECT_EQ(GlossOf(m), 0.0f);
}

TEST(SpecularTest, FresnelWeightsOfMetalsAndDielectrics) {
  const Eigen::Vector3f gold(1.0f, 0.8f, 0.3f);
  // A metal reflects its own colour head on and keeps no diffuse light.
  SpecularMix metal = SpecularMixOf(1.0f, 1.0f, gold, 1.0f);
  EXPECT_FLOAT_EQ(metal.keep, 0.0f);
  EXPECT_TRUE(metal.reflect.isApprox(gold));
  // A dielectric reflects 4 % head on and nearly everything at grazing incidence.
  SpecularMix paint = SpecularMixOf(1.0f, 0.0f, gold, 1.0f);
  EXPECT_FLOAT_EQ(paint.reflect.x(), kDielectricF0);
  EXPECT_FLOAT_EQ(paint.keep, 1.0f - kDielectricF0);
  paint = SpecularMixOf(1.0f, 0.0f, gold, 0.0f);
  EXPECT_FLOAT_EQ(paint.reflect.z(), 1.0f);
  EXPECT_FLOAT_EQ(paint.keep, 0.0f);
  // Half glossy: half of it.
  const SpecularMix half = SpecularMixOf(0.5f, 0.0f, gold, 1.0f);
  EXPECT_FLOAT_EQ(half.reflect.y(), 0.5f * kDielectricF0);
  // No gloss: the surface as before.
  const SpecularMix none = SpecularMixOf(0.0f, 1.0f, gold, 0.3f);
  EXPECT_EQ(none.keep, 1.0f);
  EXPECT_EQ(none.reflect, Eigen::Vector3f::Zero());
}

TEST(SpecularTest, MirrorDirectionObeysTheLawOfReflection) {
  const Eigen::Vector3f dir = Eigen::Vector3f(1, -1, 0).normalized(), up(0, 1, 0);
  EXPECT_TRUE(MirrorDirection(dir, up, up).isApprox(Eigen::Vector3f(1, 1, 0).normalized()));
  // A shading normal that would send the ray into the surface gives way to the geometric one.
  const Eigen::Vector3f tilted = Eigen::Vector3f(1, 0.1f, 0).normalized();
  EXPECT_GT(MirrorDirection(dir, -tilted, up).dot(up), 0.0f);
}

TEST(SpecularTest, MirrorShowsTheTargetWhereTheLawOfReflectionPutsIt) {
  const Camera camera = SmallPinhole();
  const Scene scene = MirrorScene(0.0f, 1.0f);
  Renderer renderer(scene);
  const RenderedView view = renderer.Render(camera, Rigid3d(), Opts());
  const Eigen::Vector3d image = MirrorImage(kTarget);
  const Eigen::Vector2i px = PixelOf(camera, image);
  ASSERT_GT(px.y(), PixelOf(camera, {0, kMirrorY, 30}).y());  // on the mirror, below its horizon
  // A white metal mirror reflects all: the unlit red target's own colour.
  EXPECT_EQ(Rgb(view, px), (std::array<int, 3>{255, 0, 0}));
  // Beside the image, the mirror reflects the sky, not the target.
  EXPECT_FALSE(IsRed(Rgb(view, px + Eigen::Vector2i(-6, 0))));
  EXPECT_FALSE(IsRed(Rgb(view, px + Eigen::Vector2i(0, 6))));
  // The target itself is seen directly above.
  EXPECT_EQ(view.label.at(PixelOf(camera, kTarget).x(), PixelOf(camera, kTarget).y()), kCar);
  // Ground truth is the mirror's: its label and instance, and the range to the mirror, not the target.
  EXPECT_EQ(view.label.at(px.x(), px.y()), kRoad);
  EXPECT_EQ(view.instance.at(px.x(), px.y()), kMirrorId);
  const Eigen::Vector3d bearing = *camera.CamFromImg(px.cast<double>());
  EXPECT_NEAR(view.range.at(px.x(), px.y()), kMirrorY / bearing.y() * bearing.norm(), 1e-3);
}

TEST(SpecularTest, RoughSurfacesReflectNothingAndRenderAsBefore) {
  const Camera camera = SmallPinhole();
  const Eigen::Vector2i px = PixelOf(camera, MirrorImage(kTarget));
  const Scene rough_metal = MirrorScene(0.5f, 1.0f);  // rougher than kGlossyRoughness
  const Scene default_material = MirrorScene(1.0f, 1.0f);
  RenderOptions options = Opts();
  options.samples_per_pixel = 4;
  const RenderedView rough = Renderer(rough_metal).Render(camera, Rigid3d(), options);
  const RenderedView plain = Renderer(default_material).Render(camera, Rigid3d(), options);
  EXPECT_FALSE(IsRed(Rgb(rough, px)));
  EXPECT_EQ(rough.rgb.data, plain.rgb.data);  // the same bytes as a material without roughness
}

TEST(SpecularTest, DielectricReflectsAFractionByFresnel) {
  const Camera camera = SmallPinhole();
  Scene scene = MirrorScene(0.0f, 0.0f);
  scene.materials[0].base_color_factor = Eigen::Vector4f(0, 0, 0, 1);  // black paint: only its reflection shows
  const RenderedView view = Renderer(scene).Render(camera, Rigid3d(), Opts());
  const std::array<int, 3> c = Rgb(view, PixelOf(camera, MirrorImage(kTarget)));
  EXPECT_GT(c[0], 30);       // some red from the target
  EXPECT_LT(c[0], 255 - 30);  // far from all of it: a dielectric reflects a fraction
  EXPECT_EQ(c[1], c[2]);      // nothing else but the target's red
}

TEST(SpecularTest, AMovingTargetIsReflectedWhereItIsAtTheCameraRaysTime) {
  const Camera camera = SmallPinhole();
  const Scene scene = MirrorScene(0.0f, 1.0f);
  const float before_x = -1.2f;
  const std::vector<std::vector<SceneMesh>> posed = {MirrorScene(0.0f, 1.0f, before_x).meshes, scene.meshes};
  Renderer renderer(scene);
  renderer.SetMeshesOverTime(posed, 0.0, 1.0);
  RigCamera cam{"cam", camera, Rigid3d(), 0.0};
  MovingCameraView view{&cam, 1.0, [](double) { return Rigid3d(); }};
  const RenderedView at_end = renderer.Render(view, Opts());
  const Eigen::Vector2i now = PixelOf(camera, MirrorImage(kTarget));
  const Eigen::Vector2i then = PixelOf(camera, MirrorImage({before_x, kTarget.y(), kTarget.z()}));
  EXPECT_TRUE(IsRed(Rgb(at_end, now)));
  EXPECT_FALSE(IsRed(Rgb(at_end, then)));
  view.frame_time_s = 0.0;
  const RenderedView at_start = renderer.Render(view, Opts());
  EXPECT_TRUE(IsRed(Rgb(at_start, then)));
  EXPECT_FALSE(IsRed(Rgb(at_start, now)));
}

}  // namespace
}  // namespace rigsim
