#include "renderer/renderer.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <memory>
#include <string>
#include <vector>
#include <stdexcept>

#include <gtest/gtest.h>

#include "labels/cityscapes.h"
#include "renderer/srgb.h"

namespace rigsim {
namespace {

constexpr uint8_t kRoad = 7;
constexpr uint8_t kCar = 26;

// Adds a quad p0..p3 (p0 -> p1 is the texture's u direction, p0 -> p3 its v direction) as two
// triangles with uv (0,0), (u_max,0), (u_max,v_max), (0,v_max).
int AddQuad(Scene& scene, const Eigen::Vector3f& p0, const Eigen::Vector3f& p1, const Eigen::Vector3f& p2,
            const Eigen::Vector3f& p3, uint8_t class_id, uint16_t instance_id, int material = -1, float u_max = 1,
            float v_max = 1) {
  SceneMesh mesh;
  mesh.name = "quad" + std::to_string(scene.meshes.size());
  mesh.class_id = class_id;
  mesh.instance_id = instance_id;
  mesh.material = material;
  mesh.positions = {p0, p1, p2, p3};
  mesh.texcoords = {{0, 0}, {u_max, 0}, {u_max, v_max}, {0, v_max}};
  mesh.indices = {0, 1, 2, 0, 2, 3};
  scene.meshes.push_back(mesh);
  return int(scene.meshes.size()) - 1;
}

// Fronto-parallel quad at depth z for the identity pose, spanning [x0, x1] x [y0, y1] (camera frame).
int AddFrontQuad(Scene& scene, float x0, float x1, float y0, float y1, float z, uint8_t class_id,
                 uint16_t instance_id, int material = -1, float u_max = 1, float v_max = 1) {
  return AddQuad(scene, {x0, y0, z}, {x1, y0, z}, {x1, y1, z}, {x0, y1, z}, class_id, instance_id, material, u_max,
                 v_max);
}

int AddMaterial(Scene& scene, const Eigen::Vector4f& color, int texture = -1) {
  Material m;
  m.name = "m" + std::to_string(scene.materials.size());
  m.base_color_factor = color;
  m.base_color_texture = texture;
  scene.materials.push_back(m);
  return int(scene.materials.size()) - 1;
}

// Texture from rows of RGBA texels (row 0 = top).
int AddTexture(Scene& scene, int width, int height, const std::vector<std::array<uint8_t, 4>>& texels,
               WrapMode wrap = WrapMode::kRepeat, bool nearest = true) {
  Texture t;
  t.name = "t" + std::to_string(scene.textures.size());
  t.width = width;
  t.height = height;
  for (const auto& texel : texels) t.rgba.insert(t.rgba.end(), texel.begin(), texel.end());
  t.wrap_s = t.wrap_t = wrap;
  t.nearest = nearest;
  scene.textures.push_back(t);
  return int(scene.textures.size()) - 1;
}

Camera SmallPinhole() { return Camera(CameraModelId::kPinhole, 64, 48, {50, 50, 31.5, 23.5}); }

RenderOptions Opts(int threads = 0) {
  RenderOptions o;
  o.num_threads = threads;
  return o;
}

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

// Rays through the edge two triangles share hit one of them: no crack lets the backdrop show
// through. Every quad of the grid is split along a diagonal that passes exactly through pixel
// centres, as in a glTF file with six such quads that showed 13 cracked pixels. The camera looks
// down -Z as a glTF camera does.
TEST(RendererTest, RaysThroughASharedEdgeDoNotSeeThrough) {
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

TEST(RendererTest, LabelBoundaryFallsOnTheRightPixelsPinhole) {
  const Camera camera = SmallPinhole();
  const double d = 4.0;
  // Edges at fractional pixel positions, off-centre in x and y, so that a half-pixel shift or a
  // flipped axis moves whole rows or columns across the boundary.
  auto world_x = [&](double u) { return float((u - camera.cx()) / camera.fx() * d); };
  auto world_y = [&](double v) { return float((v - camera.cy()) / camera.fy() * d); };
  Scene scene;
  AddFrontQuad(scene, world_x(20.3), world_x(45.8), world_y(10.7), world_y(30.2), float(d), kCar, 3);
  const RenderedView view = Renderer(scene).Render(camera, Rigid3d(), Opts());

  const auto top_left = camera.ImgFromCam(Eigen::Vector3d(world_x(20.3), world_y(10.7), d));
  const auto bottom_right = camera.ImgFromCam(Eigen::Vector3d(world_x(45.8), world_y(30.2), d));
  ASSERT_TRUE(top_left && bottom_right);
  int inside_count = 0;
  for (int y = 0; y < 48; ++y) {
    for (int x = 0; x < 64; ++x) {
      const bool inside = x > top_left->x() && x < bottom_right->x() && y > top_left->y() && y < bottom_right->y();
      inside_count += inside;
      ASSERT_EQ(view.label.at(x, y), inside ? kCar : kSkyId) << x << "," << y;
      ASSERT_EQ(view.instance.at(x, y), inside ? 3 : 0);
    }
  }
  EXPECT_EQ(inside_count, (45 - 21 + 1) * (30 - 11 + 1));
}

// For points along the quad's edges projected with ImgFromCam, the pixel just inside the
// projected edge has the quad's label and the pixel just outside has not.
void ExpectEdgesProjectWhereTheyShould(const Camera& camera, const std::array<Eigen::Vector3d, 4>& corners,
                                       const RenderedView& view) {
  const Eigen::Vector3d centre = 0.25 * (corners[0] + corners[1] + corners[2] + corners[3]);
  int checked = 0;
  for (int e = 0; e < 4; ++e) {
    const Eigen::Vector3d a = corners[e], b = corners[(e + 1) % 4];
    for (int i = 1; i < 40; ++i) {
      const Eigen::Vector3d p = a + (b - a) * (i / 40.0);
      const auto px = camera.ImgFromCam(p);
      const auto along = camera.ImgFromCam(p + (b - a) * 1e-4);
      const auto towards_centre = camera.ImgFromCam(p + (centre - p) * 1e-4);
      ASSERT_TRUE(px && along && towards_centre);
      const Eigen::Vector2d tangent = (*along - *px).normalized();
      Eigen::Vector2d inward(-tangent.y(), tangent.x());
      if (inward.dot(*towards_centre - *px) < 0) inward = -inward;
      // 0.9 px off the edge: the nearest pixel centre is then >= 0.19 px on the correct side.
      const Eigen::Vector2d in = (*px + 0.9 * inward).array().round();
      const Eigen::Vector2d out = (*px - 0.9 * inward).array().round();
      if (!camera.IsInImage(in) || !camera.IsInImage(out)) continue;
      EXPECT_EQ(view.label.at(int(in.x()), int(in.y())), kCar) << "edge " << e << " sample " << i << " at " << px->transpose();
      EXPECT_EQ(view.label.at(int(out.x()), int(out.y())), kSkyId) << "edge " << e << " sample " << i << " at " << px->transpose();
      ++checked;
    }
  }
  EXPECT_GT(checked, 100);
}

TEST(RendererTest, LabelBoundaryFollowsTheLensDistortion) {
  // Strong barrel distortion: edges move by several pixels against a pinhole, so a wrong sign
  // or an image-space approximation fails.
  const Camera camera(CameraModelId::kOpenCV, 64, 48, {60, 60, 31.5, 23.5, -0.3, 0, 0, 0});
  const double d = 4.0;
  const std::array<Eigen::Vector3d, 4> corners = {Eigen::Vector3d(-0.42 * d, -0.33 * d, d), Eigen::Vector3d(0.45 * d, -0.33 * d, d),
                                                  Eigen::Vector3d(0.45 * d, 0.3 * d, d), Eigen::Vector3d(-0.42 * d, 0.3 * d, d)};
  Scene scene;
  AddQuad(scene, corners[0].cast<float>(), corners[1].cast<float>(), corners[2].cast<float>(),
          corners[3].cast<float>(), kCar, 1);
  const Renderer renderer(scene);
  ExpectEdgesProjectWhereTheyShould(camera, corners, renderer.Render(camera, Rigid3d(), Opts()));

  // The pinhole check above also passes for an undistorted camera; make sure the distortion
  // actually moved the edges (the test would not catch a missing distortion otherwise).
  const Camera pinhole(CameraModelId::kPinhole, 64, 48, {60, 60, 31.5, 23.5});
  const Eigen::Vector2d corner_distorted = *camera.ImgFromCam(corners[1]);
  const Eigen::Vector2d corner_pinhole = *pinhole.ImgFromCam(corners[1]);
  EXPECT_GT((corner_distorted - corner_pinhole).norm(), 2.0);
  const RenderedView undistorted = renderer.Render(pinhole, Rigid3d(), Opts());
  const RenderedView distorted = renderer.Render(camera, Rigid3d(), Opts());
  EXPECT_NE(undistorted.label.data, distorted.label.data);
}

TEST(RendererTest, LabelBoundaryWithARotatedPose) {
  // Camera 2 m to the right and turned: exercises cam_from_world (rotation conjugate, centre).
  const Camera camera(CameraModelId::kOpenCV, 64, 48, {55, 55, 31.5, 23.5, -0.1, 0.01, 0, 0});
  const Eigen::Matrix3d r = Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitY()).toRotationMatrix() *
                            Eigen::AngleAxisd(-0.1, Eigen::Vector3d::UnitX()).toRotationMatrix();
  const Rigid3d world_from_cam(r, Eigen::Vector3d(2.0, 0.5, -1.0));
  const Rigid3d cam_from_world = world_from_cam.Inverse();
  std::array<Eigen::Vector3d, 4> corners_in_cam = {Eigen::Vector3d(-1.2, -0.9, 5), Eigen::Vector3d(1.4, -1.0, 5.5),
                                                   Eigen::Vector3d(1.3, 1.1, 6), Eigen::Vector3d(-1.0, 0.8, 5.5)};
  // Make it planar: project the 4th corner onto the plane of the first three.
  const Eigen::Vector3d n = (corners_in_cam[1] - corners_in_cam[0]).cross(corners_in_cam[2] - corners_in_cam[0]).normalized();
  corners_in_cam[3] -= n * n.dot(corners_in_cam[3] - corners_in_cam[0]);
  std::array<Eigen::Vector3d, 4> corners_in_world;
  for (int i = 0; i < 4; ++i) corners_in_world[i] = world_from_cam * corners_in_cam[i];
  Scene scene;
  AddQuad(scene, corners_in_world[0].cast<float>(), corners_in_world[1].cast<float>(),
          corners_in_world[2].cast<float>(), corners_in_world[3].cast<float>(), kCar, 1);
  const RenderedView view = Renderer(scene).Render(camera, cam_from_world, Opts());
  ExpectEdgesProjectWhereTheyShould(camera, corners_in_cam, view);
}

TEST(RendererTest, PixelsOutsideTheLensValidRegionAreEmpty) {
  // k1 = -0.3 at this focal length folds back before the image corners: those pixels have no ray.
  const Camera camera(CameraModelId::kOpenCV, 64, 48, {40, 40, 31.5, 23.5, -0.3, 0, 0, 0});
  Scene scene;
  AddFrontQuad(scene, -100, 100, -100, 100, 3, kRoad, 2);
  const RenderedView view = Renderer(scene).Render(camera, Rigid3d(), Opts());
  int invalid = 0;
  for (int y = 0; y < 48; ++y) {
    for (int x = 0; x < 64; ++x) {
      const bool valid = camera.CamFromImg(Eigen::Vector2d(x, y)).has_value();
      if (valid) {
        ASSERT_EQ(view.label.at(x, y), kRoad);
        ASSERT_GT(view.range.at(x, y), 0);
        continue;
      }
      ++invalid;
      ASSERT_EQ(view.label.at(x, y), 0);
      ASSERT_EQ(view.instance.at(x, y), 0);
      ASSERT_EQ(view.range.at(x, y), 0.0f);
      for (int c = 0; c < 3; ++c) ASSERT_EQ(view.rgb.at(x, y, c), 0);
    }
  }
  EXPECT_GT(invalid, 0);
  EXPECT_LT(invalid, 64 * 48 / 2);
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

// Colour at the image point of (x, y, z) in the camera frame.
std::array<int, 3> ColourAt(const RenderedView& view, const Camera& camera, const Eigen::Vector3d& p) {
  const Eigen::Vector2d px = *camera.ImgFromCam(p);
  const int x = int(std::lround(px.x())), y = int(std::lround(px.y()));
  return {view.rgb.at(x, y, 0), view.rgb.at(x, y, 1), view.rgb.at(x, y, 2)};
}

bool IsRed(const std::array<int, 3>& c) { return c[0] > 30 && c[1] == 0 && c[2] == 0; }
bool IsBlue(const std::array<int, 3>& c) { return c[2] > 30 && c[0] == 0 && c[1] == 0; }

TEST(RendererTest, TexcoordOriginIsTheImageTopLeft) {
  Scene scene;
  // 2 x 2: top row red, bottom row blue; the quad's uv (0, 0) corner is its top-left corner.
  const int tex = AddTexture(scene, 2, 2, {{255, 0, 0, 255}, {255, 0, 0, 255}, {0, 0, 255, 255}, {0, 0, 255, 255}});
  AddFrontQuad(scene, -1, 1, -1, 1, 3, kCar, 1, AddMaterial(scene, {1, 1, 1, 1}, tex));
  const Camera camera = SmallPinhole();
  const RenderedView view = Renderer(scene).Render(camera, Rigid3d(), Opts());
  EXPECT_TRUE(IsRed(ColourAt(view, camera, {0, -0.5, 3})));
  EXPECT_TRUE(IsBlue(ColourAt(view, camera, {0, 0.5, 3})));
}

// A 2 x 1 texture (red | blue) on a quad 3 m ahead spanning x in [-2, 2] and u in [0, 2]: u = 1
// is at x = 0 and each unit of x is half a texture width.
RenderedView RenderRedBlueOverTwoRepeats(const Camera& camera, WrapMode mode, bool nearest) {
  Scene scene;
  const int tex = AddTexture(scene, 2, 1, {{255, 0, 0, 255}, {0, 0, 255, 255}}, mode, nearest);
  AddFrontQuad(scene, -2, 2, -1, 1, 3, kCar, 1, AddMaterial(scene, {1, 1, 1, 1}, tex), 2, 1);
  return Renderer(scene).Render(camera, Rigid3d(), Opts());
}

TEST(RendererTest, WrapModes) {
  // A 2 x 1 texture (red | blue) over u in [0, 2]: four bands of half a texture-width each.
  struct Case {
    WrapMode mode;
    std::array<bool, 4> red;
  };
  for (const Case& c : {Case{WrapMode::kRepeat, {true, false, true, false}},
                        Case{WrapMode::kClampToEdge, {true, false, false, false}},
                        Case{WrapMode::kMirroredRepeat, {true, false, false, true}}}) {
    const Camera camera = SmallPinhole();
    const RenderedView view = RenderRedBlueOverTwoRepeats(camera, c.mode, /*nearest=*/true);
    for (int band = 0; band < 4; ++band) {
      const auto colour = ColourAt(view, camera, {-1.5 + band, 0, 3});
      EXPECT_TRUE(c.red[band] ? IsRed(colour) : IsBlue(colour))
          << "mode " << int(c.mode) << " band " << band << ": " << colour[0] << " " << colour[1] << " " << colour[2];
    }
  }
}

TEST(RendererTest, BilinearFilteringWrapsAcrossTheTextureEdgeAsTheSamplerSays) {
  // The same red | blue texture over u in [0, 2], filtered bilinearly. At u = 1 and u = 1.5 a
  // look-up straddles the texture's edge: repeat blends the last texel with the first (purple),
  // clamp holds the edge texel (blue), and mirrored repeat reflects (blue at u = 1; at u = 1.5 it
  // reads u = 0.5, halfway between the texels: purple).
  struct Case {
    WrapMode mode;
    std::array<bool, 2> purple;  // at u = 1 and u = 1.5
  };
  auto is_purple = [](const std::array<int, 3>& c) {
    return c[0] > 30 && c[2] > 30 && std::abs(c[0] - c[2]) < 0.25 * std::max(c[0], c[2]) && c[1] == 0;
  };
  for (const Case& c : {Case{WrapMode::kRepeat, {true, true}}, Case{WrapMode::kClampToEdge, {false, false}},
                        Case{WrapMode::kMirroredRepeat, {false, true}}}) {
    const Camera camera = SmallPinhole();
    const RenderedView view = RenderRedBlueOverTwoRepeats(camera, c.mode, /*nearest=*/false);
    for (int i = 0; i < 2; ++i) {
      const auto colour = ColourAt(view, camera, {0.0 + i, 0, 3});  // u = 1 + i / 2
      EXPECT_TRUE(c.purple[i] ? is_purple(colour) : IsBlue(colour))
          << "mode " << int(c.mode) << " u " << 1 + 0.5 * i << ": " << colour[0] << " " << colour[1] << " " << colour[2];
    }
  }
}

TEST(RendererTest, BilinearFilteringBlendsTexelCentresInLinearLight) {
  // A 2 x 1 texture, black | white, clamped and magnified over a quad spanning x in [-1, 1] at
  // 3 m: texel centres at u = 0.25 and 0.75, a linear-light blend between them. A half-texel
  // offset, or blending the sRGB codes instead of linear light, moves every mid-tone by tens of
  // codes.
  Scene scene, white;
  AddFrontQuad(scene, -1, 1, -1, 1, 3, kRoad, 1,
               AddMaterial(scene, {1, 1, 1, 1},
                           AddTexture(scene, 2, 1, {{0, 0, 0, 255}, {255, 255, 255, 255}}, WrapMode::kClampToEdge, false)));
  AddFrontQuad(white, -1, 1, -1, 1, 3, kRoad, 1,
               AddMaterial(white, {1, 1, 1, 1}, AddTexture(white, 1, 1, {{255, 255, 255, 255}})));
  const Camera camera = SmallPinhole();
  const RenderedView view = Renderer(scene).Render(camera, Rigid3d(), Opts());
  const RenderedView lit = Renderer(white).Render(camera, Rigid3d(), Opts());
  const int y = 23;
  int mid_tones = 0;
  for (int x = 16; x <= 47; ++x) {  // the quad covers x = 14.8 .. 48.2
    const double u = ((x - 31.5) * 3.0 / 50.0 + 1.0) / 2.0;  // the pixel centre's texture coordinate
    const double weight = std::clamp(2.0 * u - 0.5, 0.0, 1.0);  // of the white texel
    const double light = LinearFromSrgbCode(lit.rgb.at(x, y, 0));  // the quad is evenly lit
    EXPECT_NEAR(view.rgb.at(x, y, 0), SrgbCodeFromLinear(weight * light), 2) << "x " << x << " u " << u;
    mid_tones += weight > 0.1 && weight < 0.9;
  }
  EXPECT_GT(mid_tones, 10);
}

// A 128 x 128 black-and-white checker of 4-texel squares.
std::vector<std::array<uint8_t, 4>> Checker128() {
  std::vector<std::array<uint8_t, 4>> checker;
  for (int y = 0; y < 128; ++y) {
    for (int x = 0; x < 128; ++x) {
      const uint8_t v = ((x / 4 + y / 4) % 2) ? 255 : 0;
      checker.push_back({v, v, v, 255});
    }
  }
  return checker;
}

TEST(RendererTest, MipMappingAveragesAMinifiedChecker) {
  // A 128 x 128 checker of 4-texel squares seen at about 8.3 texels per pixel: point sampling
  // (or a mip level chosen too fine) gives a black-and-white moire; the right level (3, where a
  // texel covers 2 x 2 squares) gives the checker's mean, as a uniform texture of that mean does.
  const std::vector<std::array<uint8_t, 4>> checker = Checker128();
  const uint8_t mean_srgb = 188;  // sRGB encoding of linear 0.5
  Scene scene, uniform;
  // 0.77 m: a non-integer number of texels per pixel, so point samples do not fall on a pattern
  // that happens to average out.
  AddFrontQuad(scene, -0.4f, 0.37f, -0.4f, 0.37f, 2.5f, kRoad, 1,
               AddMaterial(scene, {1, 1, 1, 1}, AddTexture(scene, 128, 128, checker, WrapMode::kRepeat, false)));
  AddFrontQuad(uniform, -0.4f, 0.37f, -0.4f, 0.37f, 2.5f, kRoad, 1,
               AddMaterial(uniform, {1, 1, 1, 1}, AddTexture(uniform, 1, 1, {{mean_srgb, mean_srgb, mean_srgb, 255}})));
  const Camera camera = SmallPinhole();  // the quad covers 15.4 x 15.4 pixels
  const RenderedView view = Renderer(scene).Render(camera, Rigid3d(), Opts());
  const RenderedView reference = Renderer(uniform).Render(camera, Rigid3d(), Opts());
  int checked = 0;
  for (int y = 18; y <= 29; ++y) {
    for (int x = 26; x <= 37; ++x) {
      ASSERT_EQ(view.label.at(x, y), kRoad);
      EXPECT_NEAR(view.rgb.at(x, y, 0), reference.rgb.at(x, y, 0), 6) << x << "," << y;
      ++checked;
    }
  }
  EXPECT_EQ(checked, 144);
}

TEST(RendererTest, MinificationFilterOfTheSamplerIsHonoured) {
  // The minified checker of MipMappingAveragesAMinifiedChecker under other glTF minFilters: without
  // mip levels (NEAREST) each pixel is one texel, black or white; LINEAR_MIPMAP_NEAREST reads the
  // nearest level (3), whose texels are the checker's mean.
  const std::vector<std::array<uint8_t, 4>> checker = Checker128();
  auto render = [&](bool min_nearest, MipFilter mip, const std::vector<std::array<uint8_t, 4>>& texels) {
    Scene scene;
    const int size = texels.size() == 1 ? 1 : 128;
    const int tex = AddTexture(scene, size, size, texels, WrapMode::kRepeat, false);
    scene.textures[tex].min_nearest = min_nearest;
    scene.textures[tex].mip = mip;
    AddFrontQuad(scene, -0.4f, 0.37f, -0.4f, 0.37f, 2.5f, kRoad, 1, AddMaterial(scene, {1, 1, 1, 1}, tex));
    return Renderer(scene).Render(SmallPinhole(), Rigid3d(), Opts());
  };
  const RenderedView point = render(true, MipFilter::kNone, checker);
  const RenderedView nearest_level = render(false, MipFilter::kNearest, checker);
  const RenderedView trilinear = render(false, MipFilter::kLinear, checker);
  const RenderedView white_texture = render(false, MipFilter::kLinear, {{255, 255, 255, 255}});
  int black = 0, white = 0;
  for (int y = 18; y <= 29; ++y) {
    for (int x = 26; x <= 37; ++x) {
      const int v = point.rgb.at(x, y, 0);
      black += v == 0;
      white += v == white_texture.rgb.at(x, y, 0);
      EXPECT_NEAR(nearest_level.rgb.at(x, y, 0), trilinear.rgb.at(x, y, 0), 6) << x << "," << y;
    }
  }
  EXPECT_EQ(black + white, 144);  // every pixel is one texel (the mix depends on how the grids beat)
  EXPECT_GT(black, 10);
  EXPECT_GT(white, 10);
}

TEST(RendererTest, AlphaMaskCutsOutGeometryInEveryOutput) {
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

// COLOR_0 (glTF 2.0) multiplies the base colour factor, is interpolated across the triangles, and
// its alpha takes part in the MASK test; without a material the colours show as they are.
TEST(RendererTest, VertexColoursMultiplyTheBaseColourAndTheirAlphaCutsOut) {
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
TEST(RendererTest, UnlitMaterialsShowTheirBaseColour) {
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
TEST(RendererTest, EmissionAddsToTheReflectedLight) {
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
TEST(RendererTest, EmissiveTextureUsesItsOwnTexcoords) {
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
TEST(RendererTest, NormalMapsTurnTheShadingNormal) {
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
TEST(RendererTest, OcclusionScalesTheSkyLightOnly) {
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

// The pixel-centre bearings Render traces: CamFromImg's, normalised, and zero outside the lens.
TEST(RendererTest, PixelCentreBearingsAreTheCameraModelsRays) {
  const Camera fisheye(CameraModelId::kOpenCVFisheye, 64, 48, {12, 12, 31.5, 23.5, 0.05, -0.01, 0, 0});
  const Scene empty;
  const std::shared_ptr<const std::vector<Eigen::Vector3f>> kept = Renderer(empty).PixelCentreBearings(fisheye);
  const std::vector<Eigen::Vector3f>& bearings = *kept;  // outlives the renderer: the pointer keeps it
  ASSERT_EQ(bearings.size(), size_t(64 * 48));
  int outside = 0;
  for (int y = 0; y < 48; ++y) {
    for (int x = 0; x < 64; ++x) {
      const Eigen::Vector3f& b = bearings[size_t(y) * 64 + x];
      const auto ray = fisheye.CamFromImg(Eigen::Vector2d(x, y));
      if (!ray) {
        EXPECT_TRUE(b.isZero()) << x << ", " << y;
        ++outside;
        continue;
      }
      EXPECT_LT((b.cast<double>() - ray->normalized()).norm(), 1e-6) << x << ", " << y;
    }
  }
  EXPECT_GT(outside, 0);  // the corners lie beyond the lens's valid image circle
}

TEST(RendererTest, SunLightAndHardShadows) {
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
  try {
    Renderer renderer(scene);
    FAIL() << "expected an exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("broken.glb"), std::string::npos) << e.what();
  }
  scene.meshes[0].indices = {0, 1, 2};
  scene.meshes[0].colors = {Eigen::Vector4f::Ones()};  // one colour for four vertices
  try {
    Renderer renderer(scene);
    FAIL() << "expected an exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("1 vertex colours for 4 positions"), std::string::npos) << e.what();
  }
}

TEST(RendererTest, EmptySceneIsAllSky) {
  const RenderedView view = Renderer(Scene()).Render(SmallPinhole(), Rigid3d(), Opts());
  for (uint8_t label : view.label.data) ASSERT_EQ(label, kSkyId);
  for (float r : view.range.data) ASSERT_EQ(r, 0.0f);
}

}  // namespace
}  // namespace rigsim
