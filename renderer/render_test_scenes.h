// Small scenes and cameras for the renderer's unit tests: quads with texture coordinates,
// materials, textures from rows of texels, and the poses and pixel look-ups the tests share.
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "geometry/camera.h"
#include "geometry/rigid3.h"
#include "renderer/renderer.h"
#include "scene/scene.h"

namespace rigsim {

constexpr uint8_t kRoad = 7;
constexpr uint8_t kCar = 26;

// Adds a quad p0..p3 (p0 -> p1 is the texture's u direction, p0 -> p3 its v direction) as two
// triangles with uv (0,0), (u_max,0), (u_max,v_max), (0,v_max).
inline int AddQuad(Scene& scene, const Eigen::Vector3f& p0, const Eigen::Vector3f& p1, const Eigen::Vector3f& p2,
                   const Eigen::Vector3f& p3, uint8_t class_id, uint16_t instance_id, int material = -1,
                   float u_max = 1, float v_max = 1) {
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
inline int AddFrontQuad(Scene& scene, float x0, float x1, float y0, float y1, float z, uint8_t class_id,
                        uint16_t instance_id, int material = -1, float u_max = 1, float v_max = 1) {
  return AddQuad(scene, {x0, y0, z}, {x1, y0, z}, {x1, y1, z}, {x0, y1, z}, class_id, instance_id, material, u_max,
                 v_max);
}

inline int AddMaterial(Scene& scene, const Eigen::Vector4f& color, int texture = -1) {
  Material m;
  m.name = "m" + std::to_string(scene.materials.size());
  m.base_color_factor = color;
  m.base_color_texture = texture;
  scene.materials.push_back(m);
  return int(scene.materials.size()) - 1;
}

// Texture from rows of RGBA texels (row 0 = top).
inline int AddTexture(Scene& scene, int width, int height, const std::vector<std::array<uint8_t, 4>>& texels,
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

inline Camera SmallPinhole() { return Camera(CameraModelId::kPinhole, 64, 48, {50, 50, 31.5, 23.5}); }

inline RenderOptions Opts(int threads = 0) {
  RenderOptions o;
  o.num_threads = threads;
  return o;
}

// Colour at the image point of (x, y, z) in the camera frame.
inline std::array<int, 3> ColourAt(const RenderedView& view, const Camera& camera, const Eigen::Vector3d& p) {
  const Eigen::Vector2d px = *camera.ImgFromCam(p);
  const int x = int(std::lround(px.x())), y = int(std::lround(px.y()));
  return {view.rgb.at(x, y, 0), view.rgb.at(x, y, 1), view.rgb.at(x, y, 2)};
}

inline bool IsRed(const std::array<int, 3>& c) { return c[0] > 30 && c[1] == 0 && c[2] == 0; }
inline bool IsBlue(const std::array<int, 3>& c) { return c[2] > 30 && c[0] == 0 && c[1] == 0; }

}  // namespace rigsim
