// glTF features checked through the renderer, from a file on disk to pixels:
//  - a glTF camera used as a rig camera (gltf/scene_cameras.h) sees the file's view: a target on
//    the camera's view axis lands at the principal point, glTF "up" is image up;
//  - KHR_texture_transform changes what part of the texture a surface shows;
//  - vertex colours (COLOR_0) colour a surface without a material or texture;
//  - EXT_mesh_gpu_instancing draws every instance, each its own object in the instance image.
#include <array>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <set>
#include <string>
#include <vector>

#include <Eigen/Geometry>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "gltf/gltf_loader.h"
#include "gltf/scene_cameras.h"
#include "labels/cityscapes.h"
#include "renderer/renderer.h"
#include "renderer/srgb.h"
#include "testing/gltf_builder.h"
#include "testing/temp_dir.h"

namespace rigsim {
namespace {

using nlohmann::json;
namespace fs = std::filesystem;

uint8_t ClassId(const char* name) { return FindClassByName(name)->id; }

// cam_from_world for a camera at the origin looking down world -Z with +Y up (OpenCV axes).
Eigen::Matrix3d LookingDownMinusZ() {
  Eigen::Matrix3d r;
  r << 1, 0, 0, 0, -1, 0, 0, 0, -1;
  return r;
}

// What `camera` at the origin looking down -Z sees of `scene`, with or without sun shadows.
RenderedView RenderFromOrigin(const Scene& scene, const Camera& camera, bool shadows) {
  RenderOptions options;
  options.shadows = shadows;
  return Renderer(scene).Render(camera, Rigid3d(LookingDownMinusZ(), Eigen::Vector3d::Zero()), options);
}

TEST(GltfFeaturesRender, GltfCameraSeesTheFilesViewCentreAtThePrincipalPoint) {
  GltfBuilder g;
  // The reference camera (node 0) somewhere else; the tested camera (node 2) is a child of a mount
  // turned 30 deg about +Y and lifted 1.5 m, itself tilted 10 deg down about its x axis.
  const double yfov = 50.0 * std::numbers::pi / 180.0;
  g.doc["cameras"] = {{{"type", "perspective"}, {"perspective", {{"yfov", yfov}, {"znear", 0.05}}}}};
  const Eigen::Quaterniond mount_q(Eigen::AngleAxisd(30.0 * std::numbers::pi / 180.0, Eigen::Vector3d::UnitY()));
  const Eigen::Quaterniond cam_q(Eigen::AngleAxisd(-10.0 * std::numbers::pi / 180.0, Eigen::Vector3d::UnitX()));
  const Eigen::Vector3d mount_t(0.3, 1.5, -0.2);
  g.doc["nodes"].push_back({{"name", "reference"}, {"camera", 0}, {"translation", {5, 1, 5}}});
  g.doc["nodes"].push_back({{"name", "mount"}, {"translation", {mount_t.x(), mount_t.y(), mount_t.z()}},
                            {"rotation", {mount_q.x(), mount_q.y(), mount_q.z(), mount_q.w()}}, {"children", {2}}});
  g.doc["nodes"].push_back({{"name", "tilted"}, {"camera", 0}, {"rotation", {cam_q.x(), cam_q.y(), cam_q.z(), cam_q.w()}}});
  g.Scene({0, 1});
  // The glTF camera frame of "tilted" in the world: right, up and view (-Z) directions.
  const Eigen::Matrix3d world_from_gl = (mount_q * cam_q).toRotationMatrix();
  const Eigen::Vector3d right = world_from_gl.col(0), up = world_from_gl.col(1), view = -world_from_gl.col(2);
  g.Square(mount_t + 8.0 * view, right, up, 0.4, "pole");                        // on the view axis
  g.Square(mount_t + 8.0 * view + 1.5 * up, right, up, 0.4, "traffic sign");    // above it
  g.Square(mount_t + 20.0 * view, right, up, 60.0, "building");                  // background
  const Scene scene = LoadGltf(g.WriteEmbedded(TempDir(), "cameras"));

  // Odd image sizes put the principal point on a pixel centre.
  const SceneCameraRig r = RigFromSceneCameras(scene, 161, 121);
  ASSERT_EQ(r.rig.cameras.size(), 2u);
  const RigCamera& cam = r.rig.cameras[1];
  ASSERT_EQ(cam.name, "tilted");
  EXPECT_EQ(cam.camera.cx(), 80.0);
  EXPECT_EQ(cam.camera.cy(), 60.0);
  const Rigid3d cam_from_world = *cam.cam_from_rig * *r.frames.frames[0].rig_from_world;
  const Renderer renderer(scene);
  RenderOptions options;
  options.num_threads = 2;
  const RenderedView view_img = renderer.Render(cam.camera, cam_from_world, options);

  EXPECT_EQ(view_img.label.at(80, 60), ClassId("pole"));
  EXPECT_NEAR(view_img.range.at(80, 60), 8.0, 1e-3);
  // The target's pixels are centred on the principal point, the sign's straight above it.
  auto centroid = [&](uint8_t id) {
    Eigen::Vector2d sum = Eigen::Vector2d::Zero();
    int n = 0;
    for (int y = 0; y < 121; ++y) {
      for (int x = 0; x < 161; ++x) {
        if (view_img.label.at(x, y) == id) {
          sum += Eigen::Vector2d(x, y);
          ++n;
        }
      }
    }
    EXPECT_GT(n, 4) << int(id);
    return Eigen::Vector2d(sum / std::max(n, 1));
  };
  const Eigen::Vector2d pole = centroid(ClassId("pole"));
  EXPECT_LT((pole - Eigen::Vector2d(80, 60)).norm(), 0.01) << pole.transpose();
  const Eigen::Vector2d sign = centroid(ClassId("traffic sign"));
  EXPECT_NEAR(sign.x(), 80.0, 0.01);
  EXPECT_NEAR(sign.y(), 60.0 - cam.camera.fy() * 1.5 / 8.0, 0.5) << "glTF up must be image up";
}

// A 2x1 texture, left texel red, right texel green, sampled NEAREST with clamping.
int AddRedGreenTexture(GltfBuilder& g) {
  cv::Mat bgr(1, 2, CV_8UC3);
  bgr.at<cv::Vec3b>(0, 0) = cv::Vec3b(0, 0, 255);
  bgr.at<cv::Vec3b>(0, 1) = cv::Vec3b(0, 255, 0);
  std::vector<uint8_t> png;
  cv::imencode(".png", bgr, png);
  g.doc["images"] = {{{"uri", DataUri("image/png", png)}}};
  g.doc["samplers"] = {{{"magFilter", 9728}, {"minFilter", 9728}, {"wrapS", 33071}, {"wrapT", 33071}}};
  g.doc["textures"] = {{{"source", 0}, {"sampler", 0}}};
  return 0;
}

TEST(GltfFeaturesRender, TextureTransformSelectsThePartOfTheTextureShown) {
  // Four textured squares side by side facing a camera at the origin looking down -Z, uv (0, 0) at
  // each one's top-left corner:
  //  0 plain: left half red, right half green;
  //  1 offset (0.5, 0), scale (0.5, 1): only the right texel, all green;
  //  2 rotation 180 deg, offset (1, 1): uv -> (1-u, 1-v), mirrored, left half green;
  //  3 rotation 90 deg: uv -> (v, -u) (counter-clockwise in the v-down UV plane), so the texture's
  //    columns run down the square: top half red, bottom half green. The opposite direction,
  //    (-v, u), would clamp to the red texel everywhere.
  GltfBuilder g;
  AddRedGreenTexture(g);
  const double pi = std::numbers::pi;
  auto material = [&](json ext) {
    json info = {{"index", 0}};
    if (!ext.is_null()) info["extensions"] = {{"KHR_texture_transform", ext}};
    return json{{"pbrMetallicRoughness", {{"baseColorTexture", info}}}};
  };
  g.doc["materials"] = {material(nullptr), material({{"offset", {0.5, 0}}, {"scale", {0.5, 1}}}),
                        material({{"offset", {1, 1}}, {"rotation", pi}}), material({{"rotation", pi / 2}})};
  g.doc["extensionsUsed"] = {"KHR_texture_transform"};
  const Eigen::Vector3d right(1, 0, 0), up(0, 1, 0);
  auto centre = [](int square) { return Eigen::Vector3d(-3.3 + 2.2 * square, 0, -6); };
  for (int m = 0; m < 4; ++m) g.Square(centre(m), right, up, 2.0, "wall", m);
  const Scene scene = LoadGltf(g.WriteEmbedded(TempDir(), "texture_transform"));
  ASSERT_TRUE(scene.warnings.empty()) << scene.warnings.front();

  const Camera camera = Camera::PinholeFromHorizontalFov(300, 100, 90.0);
  const Eigen::Matrix3d cam_from_world_r = LookingDownMinusZ();
  const RenderedView v = RenderFromOrigin(scene, camera, /*shadows=*/false);
  // Colour at a fraction across (from the left) and down (from the top) of a square.
  auto colour_at = [&](int square, double across, double down) {
    const Eigen::Vector3d p = centre(square) + Eigen::Vector3d(-1.0 + 2.0 * across, 1.0 - 2.0 * down, 0);
    const auto px = camera.ImgFromCam(cam_from_world_r * p);
    const int x = int(std::lround(px->x())), y = int(std::lround(px->y()));
    EXPECT_EQ(v.label.at(x, y), ClassId("wall"));
    const int r = v.rgb.at(x, y, 0), gr = v.rgb.at(x, y, 1);
    return r > 2 * gr + 10 ? 'R' : gr > 2 * r + 10 ? 'G' : '?';
  };
  EXPECT_EQ(colour_at(0, 0.25, 0.5), 'R');
  EXPECT_EQ(colour_at(0, 0.75, 0.5), 'G');
  EXPECT_EQ(colour_at(1, 0.25, 0.5), 'G') << "offset 0.5, scale 0.5 shows only the right texel";
  EXPECT_EQ(colour_at(1, 0.75, 0.5), 'G');
  EXPECT_EQ(colour_at(2, 0.25, 0.5), 'G') << "rotation by 180 deg mirrors u";
  EXPECT_EQ(colour_at(2, 0.75, 0.5), 'R');
  EXPECT_EQ(colour_at(3, 0.5, 0.25), 'R') << "rotation by 90 deg: u' = v";
  EXPECT_EQ(colour_at(3, 0.5, 0.75), 'G') << "rotation by 90 deg: u' = v";
}

TEST(GltfFeaturesRender, VertexColoursColourASurfaceWithoutMaterial) {
  // One square 5 m down -Z: red on its left edge, green on its right, no material.
  GltfBuilder g;
  const Eigen::Vector4f red(1, 0, 0, 1), green(0, 1, 0, 1);
  g.Quad({Eigen::Vector3d(-1, 1, -5), Eigen::Vector3d(1, 1, -5), Eigen::Vector3d(1, -1, -5), Eigen::Vector3d(-1, -1, -5)},
         "wall", -1, {red, green, green, red});
  const Scene scene = LoadGltf(g.WriteEmbedded(TempDir(), "vertex_colours"));
  ASSERT_TRUE(scene.warnings.empty()) << scene.warnings.front();

  const Camera camera = Camera::PinholeFromHorizontalFov(100, 100, 60.0);
  const Eigen::Matrix3d cam_from_world_r = LookingDownMinusZ();
  const RenderedView v = RenderFromOrigin(scene, camera, /*shadows=*/false);
  auto rgb_at = [&](double x) {
    const auto px = camera.ImgFromCam(cam_from_world_r * Eigen::Vector3d(x, 0, -5));
    const int u = int(std::lround(px->x())), w = int(std::lround(px->y()));
    EXPECT_EQ(v.label.at(u, w), ClassId("wall"));
    return std::array<int, 3>{v.rgb.at(u, w, 0), v.rgb.at(u, w, 1), v.rgb.at(u, w, 2)};
  };
  const std::array<int, 3> left = rgb_at(-0.8), middle = rgb_at(0.0), right = rgb_at(0.8);
  // In linear light, 0.8 of the way across is 9 parts of one colour to 1 of the other.
  auto linear = [](int code) { return LinearFromSrgbCode(uint8_t(code)); };
  EXPECT_NEAR(linear(left[0]) / linear(left[1]), 9.0, 1.0) << "red side";
  EXPECT_NEAR(linear(right[1]) / linear(right[0]), 9.0, 1.0) << "green side";
  EXPECT_NEAR(linear(middle[0]) / linear(middle[1]), 1.0, 0.1) << "half way (within a pixel): as much red as green";
  EXPECT_EQ(left[2], 0);
  EXPECT_EQ(right[2], 0);
}

// One square node, 5 m down -Z, drawn by three instances 1.5 m apart along x (the middle one
// turned 45 deg about z): each shows at its own place with its own id, nothing between them.
TEST(GltfFeaturesRender, GpuInstancesAreSeparateObjectsInTheInstanceImage) {
  GltfBuilder g;
  g.doc["extensionsUsed"] = {"EXT_mesh_gpu_instancing"};
  g.doc["extensionsRequired"] = {"EXT_mesh_gpu_instancing"};
  g.Square(Eigen::Vector3d(0, 0, -5), Eigen::Vector3d::UnitX(), Eigen::Vector3d::UnitY(), 0.8, "vegetation");
  const float s = float(std::sin(std::numbers::pi / 8)), c = float(std::cos(std::numbers::pi / 8));
  const int t = g.Floats({-1.5f, 0, 0, 0, 0, 0, 1.5f, 0, 0}, "VEC3");
  const int r = g.Floats({0, 0, 0, 1, 0, 0, s, c, 0, 0, 0, 1}, "VEC4");
  g.doc["nodes"].back()["extensions"] = {{"EXT_mesh_gpu_instancing", {{"attributes", {{"TRANSLATION", t}, {"ROTATION", r}}}}}};
  const Scene scene = LoadGltf(g.WriteEmbedded(TempDir(), "instanced"));
  ASSERT_TRUE(scene.warnings.empty()) << scene.warnings.front();
  ASSERT_EQ(scene.meshes.size(), 3u);

  const Camera camera = Camera::PinholeFromHorizontalFov(160, 100, 60.0);
  const Eigen::Matrix3d cam_from_world_r = LookingDownMinusZ();
  const RenderedView v = RenderFromOrigin(scene, camera, /*shadows=*/false);
  auto pixel = [&](double x, double y) {
    const auto px = camera.ImgFromCam(cam_from_world_r * Eigen::Vector3d(x, y, -5));
    return std::array<int, 2>{int(std::lround(px->x())), int(std::lround(px->y()))};
  };
  std::set<uint16_t> seen;
  for (int i = 0; i < 3; ++i) {
    const auto [u, w] = pixel(1.5 * (i - 1), 0.0);
    EXPECT_EQ(v.instance.at(u, w), scene.meshes[i].instance_id) << "instance " << i;
    EXPECT_EQ(v.label.at(u, w), ClassId("vegetation")) << "instance " << i;
    seen.insert(v.instance.at(u, w));
    const auto [gu, gw] = pixel(1.5 * (i - 1) + (i == 0 ? 0.75 : -0.75), 0.0);  // the gaps
    EXPECT_EQ(v.instance.at(gu, gw), 0) << "beside instance " << i;
  }
  EXPECT_EQ(seen.size(), 3u);
  EXPECT_EQ(seen.count(0), 0u);
  // The turned instance reaches its corners' diagonal (0.4 * sqrt 2 along x), the others do not.
  const auto [du, dw] = pixel(0.52, 0.0);
  EXPECT_EQ(v.instance.at(du, dw), scene.meshes[1].instance_id);
  const auto [eu, ew] = pixel(1.5 - 0.52, 0.0);
  EXPECT_EQ(v.instance.at(eu, ew), 0);
}

// A black surface with emissiveFactor scaled by KHR_materials_emissive_strength shows exactly
// that light, whatever the sun and sky.
TEST(GltfFeaturesRender, EmissiveSurfaceShowsItsEmission) {
  GltfBuilder g;
  g.doc["extensionsUsed"] = {"KHR_materials_emissive_strength"};
  g.doc["materials"] = {{{"pbrMetallicRoughness", {{"baseColorFactor", {0, 0, 0, 1}}}},
                         {"emissiveFactor", {0.2, 0.1, 0.05}},
                         {"extensions", {{"KHR_materials_emissive_strength", {{"emissiveStrength", 2}}}}}}};
  g.Square(Eigen::Vector3d(0, 0, -5), Eigen::Vector3d::UnitX(), Eigen::Vector3d::UnitY(), 2, "wall", 0);
  const Scene scene = LoadGltf(g.WriteEmbedded(TempDir(), "emissive"));
  ASSERT_TRUE(scene.warnings.empty()) << scene.warnings.front();

  const Camera camera = Camera::PinholeFromHorizontalFov(100, 100, 60.0);
  const RenderedView v = RenderFromOrigin(scene, camera, /*shadows=*/true);
  const float expected[3] = {0.4f, 0.2f, 0.1f};
  for (int c = 0; c < 3; ++c) EXPECT_EQ(v.rgb.at(50, 50, c), SrgbCodeFromLinear(expected[c])) << c;
}

}  // namespace
}  // namespace rigsim
