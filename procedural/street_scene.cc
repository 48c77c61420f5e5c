#include "procedural/street_scene.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "gltf/scene_builder.h"
#include "procedural/glass_and_water.h"
#include "procedural/motion.h"
#include "procedural/objects.h"
#include "procedural/textures.h"

namespace rigsim {
namespace {

using namespace procedural;  // NOLINT: the painters and builders are this file's vocabulary

using Eigen::Vector2f;
using Eigen::Vector3f;

constexpr float kStreetHalfLength = 60.f;
constexpr float kRoadHalfWidth = 5.f;
constexpr float kFacadeX = 9.f;
constexpr float kCurbHeight = 0.15f;
constexpr float kNearPpm = 72.f;  // texels per metre on surfaces near the origin
constexpr float kFarPpm = 40.f;   // further away, where they cover fewer pixels

// Asphalt for the road segment x in [-5, 5], z in [z0, z0 + len]; texture u along +x, v along +z.
Canvas PaintRoad(uint64_t seed, float z0, float len, float ppm) {
  Rng rng(seed);
  const float width = 2 * kRoadHalfWidth;
  const int w = int(width * ppm), h = int(len * ppm);
  Canvas c(w, h, Vector3f(0.27f, 0.27f, 0.28f));
  auto U = [&](float x) { return (x + kRoadHalfWidth) * ppm; };
  auto V = [&](float z) { return (z - z0) * ppm; };
  AddNoise(c, rng.Fork(), 0.07f, 64);
  // Repair patches with sharp edges and their own grain.
  for (int i = 0, n = rng.Int(2, 6); i < n; ++i) {
    const float x = rng.Uniform(0, float(w)), y = rng.Uniform(0, float(h));
    const float pw = rng.Uniform(0.5f, 2.5f) * ppm, ph = rng.Uniform(0.5f, 3.f) * ppm, tone = rng.Uniform(0.18f, 0.36f);
    FillRect(c, x, y, x + pw, y + ph, Vector3f::Constant(tone), 0.8f);
  }
  // Aggregate: light and dark speckles at a few sizes.
  for (int i = 0, n = int(width * len * 25); i < n; ++i) {
    const float r = rng.Uniform(0.6f, 2.2f), ex = rng.Uniform(0, float(w)), ey = rng.Uniform(0, float(h));
    const float tone = rng.Chance(0.5f) ? 0.55f : 0.12f;
    FillEllipse(c, ex, ey, r, r, Vector3f::Constant(tone), 0.6f);
  }
  // Oil stains.
  for (int i = 0, n = rng.Int(1, 4); i < n; ++i) {
    const float ex = rng.Uniform(0, float(w)), ey = rng.Uniform(0, float(h));
    const float rx = rng.Uniform(0.2f, 0.6f) * ppm, ry = rng.Uniform(0.2f, 0.6f) * ppm;
    FillEllipse(c, ex, ey, rx, ry, Vector3f(0.1f, 0.1f, 0.1f), 0.35f);
  }
  // Lane markings in world coordinates, so that they continue across segments.
  const Vector3f paint(0.9f, 0.9f, 0.86f);
  auto Worn = [&](float x0, float y0, float x1, float y1) {
    for (int y = std::max(0, int(y0)); y < std::min(h, int(y1)); ++y) {
      for (int x = std::max(0, int(x0)); x < std::min(w, int(x1)); ++x) {
        const float wear = ValueNoise(x / 5.f, y / 5.f, seed + 11);
        if (wear > 0.25f) c.Blend(x, y, paint, 0.9f);
      }
    }
  };
  for (float z = std::floor(z0 / 9.f) * 9.f; z < z0 + len; z += 9.f) Worn(U(-0.06f), V(z), U(0.06f), V(z + 3.f));  // centre dashes
  Worn(U(-4.7f), 0, U(-4.58f), float(h));
  Worn(U(4.58f), 0, U(4.7f), float(h));
  // A zebra crossing near z = 8 m.
  if (z0 <= 9.f && z0 + len >= 6.f) {
    for (float x = -4.2f; x < 4.2f; x += 1.0f) Worn(U(x), V(6.f), U(x + 0.5f), V(9.f));
  }
  // Cracks: thin random walks.
  for (int i = 0, n = rng.Int(3, 9); i < n; ++i) {
    float x = rng.Uniform(0, float(w)), y = rng.Uniform(0, float(h)), a = rng.Uniform(0, 2 * kPi);
    for (int k = 0, steps = rng.Int(10, 40); k < steps; ++k) {
      a += rng.Uniform(-0.7f, 0.7f);
      const float nx = x + std::cos(a) * 0.08f * ppm, ny = y + std::sin(a) * 0.08f * ppm;
      Stroke(c, x, y, nx, ny, 1.2f, Vector3f(0.06f, 0.06f, 0.06f), 0.9f);
      x = nx;
      y = ny;
    }
  }
  // Manhole covers: a ring and a grid of bosses.
  for (int i = 0, n = rng.Chance(0.7f) ? rng.Int(1, 2) : 0; i < n; ++i) {
    const float cx = rng.Uniform(1.f, width - 1.f) * ppm, cy = rng.Uniform(1.f, len - 1.f) * ppm, r = 0.32f * ppm;
    FillEllipse(c, cx, cy, r, r, Vector3f(0.2f, 0.19f, 0.18f));
    FillEllipse(c, cx, cy, r * 0.88f, r * 0.88f, Vector3f(0.33f, 0.31f, 0.29f));
    for (float gy = -r * 0.7f; gy <= r * 0.7f; gy += 0.07f * ppm) {
      for (float gx = -r * 0.7f; gx <= r * 0.7f; gx += 0.07f * ppm) {
        if (gx * gx + gy * gy < r * r * 0.6f) FillEllipse(c, cx + gx, cy + gy, 0.015f * ppm + 0.5f, 0.015f * ppm + 0.5f, Vector3f(0.15f, 0.15f, 0.14f));
      }
    }
  }
  return c;
}

// Paving for a sidewalk strip 4 m wide (u across, starting at the curb) by `len` m (v along z).
Canvas PaintSidewalk(uint64_t seed, float len, float ppm) {
  Rng rng(seed);
  const float width = kFacadeX - kRoadHalfWidth;
  const int w = int(width * ppm), h = int(len * ppm);
  const Vector3f base = Vector3f::Constant(rng.Uniform(0.5f, 0.62f));
  Canvas c(w, h, base);
  const float slab = rng.Uniform(0.4f, 0.6f) * ppm, joint = std::max(1.f, 0.01f * ppm);
  for (float y = 0; y < h; y += slab) {
    for (float x = 0.3f * ppm; x < w; x += slab) {
      FillRect(c, x + joint, y + joint, x + slab - joint, y + slab - joint, base * rng.Uniform(0.85f, 1.12f));
      if (rng.Chance(0.05f)) {  // cracked slab
        const float ya = y + rng.Uniform(0, slab), yb = y + rng.Uniform(0, slab);
        Stroke(c, x, ya, x + slab, yb, 1.2f, base * 0.4f);
      }
    }
  }
  // Curb stones along the road edge (u = 0).
  for (float y = 0; y < h; y += 0.8f * ppm) FillRect(c, 0, y + joint, 0.3f * ppm - joint, y + 0.8f * ppm - joint, Vector3f::Constant(rng.Uniform(0.62f, 0.75f)));
  AddNoise(c, rng.Fork(), 0.08f, 32);
  for (int i = 0, n = int(width * len * 20); i < n; ++i) {  // grit: small light and dark speckles
    const float r = rng.Uniform(0.6f, 2.f), ex = rng.Uniform(0, float(w)), ey = rng.Uniform(0, float(h));
    const float tone = rng.Chance(0.5f) ? 0.8f : 0.25f;
    FillEllipse(c, ex, ey, r, r, Vector3f::Constant(tone), 0.6f);
  }
  for (int i = 0, n = int(width * len * 0.3f); i < n; ++i) {  // water stains and fallen leaves
    const float r = rng.Uniform(0.05f, 0.3f) * ppm, ex = rng.Uniform(0, float(w)), ey = rng.Uniform(0, float(h));
    const float ry = r * rng.Uniform(0.4f, 1.f);
    const Vector3f col = rng.Chance(0.5f) ? Vector3f(0.35f, 0.33f, 0.3f) : Vector3f(0.55f, 0.4f, 0.15f);
    FillEllipse(c, ex, ey, r, ry, col, 0.5f);
  }
  for (int i = 0, n = int(width * len * 3); i < n; ++i) {  // gum and stains
    const float r = rng.Uniform(0.8f, 0.04f * ppm), ex = rng.Uniform(0, float(w)), ey = rng.Uniform(0, float(h));
    const float tone = rng.Uniform(0.15f, 0.35f);
    FillEllipse(c, ex, ey, r, r, Vector3f::Constant(tone), 0.7f);
  }
  if (rng.Chance(0.4f)) {
    const float gx = rng.Uniform(0, float(w)), gy = rng.Uniform(0, float(h));
    Graffiti(c, rng, gx, gy, 0.8f * ppm);
  }
  return c;
}


// ---------------------------------------------------------------------------------------------

class StreetGenerator {
 public:
  // The motion and the puddles draw from their own streams, so that the rest of the scene is the
  // same with and without them; the glass draws nothing (it lies on the painted windows).
  StreetGenerator(uint64_t seed, bool glass, double wet)
      : rng_(seed), motion_rng_(seed ^ 0x9e3779b97f4a7c15ull), wet_rng_(seed ^ 0xc2b2ae3d27d4eb4full), glass_(glass), wet_(wet) {}

  SceneBuilder Build(bool animated = false, double traffic = 0) {
    Road();
    Sidewalks();
    Buildings();
    EndBuildings();
    Lamps();
    Signs();
    Railing();
    Cars();
    People();
    Trees();
    if (animated) Animate(traffic);  // after everything else: the static scene is the same either way
    return std::move(b_);
  }

 private:
  // A material showing `c`; `texture` receives the texture's index, for the glossy parts over it.
  int Material(const std::string& name, const Canvas& c, int* texture = nullptr) {
    const int tex = b_.AddTexture(name, c.w, c.h, 3, c.ToRgb8());
    if (texture != nullptr) *texture = tex;
    return b_.AddMaterial(name, Eigen::Vector4f::Ones(), tex);
  }

  // `parts` (the facade first), and the glass of the facade's `panes` when the street has glass:
  // one node, so the glass is the building's class and instance.
  void AddFacadeNode(const std::string& name, std::vector<MeshPart> parts, const Vector3f& tl, const Vector3f& right,
                     const Vector3f& down, const Canvas& facade, int facade_texture, const std::vector<Pane>& panes) {
    MeshData glass = GlassPanes(tl, right, down, facade.w, facade.h, panes);
    if (!glass.indices.empty()) parts.push_back({std::move(glass), GlassMaterial(b_, name + "_glass", facade_texture)});
    b_.AddNode(name, "building", std::move(parts));
  }
  static float PpmAt(float z_near) { return std::abs(z_near) < 25.f ? kNearPpm : kFarPpm; }
  static float NearestAbs(float z0, float z1) { return (z0 <= 0 && z1 >= 0) ? 0.f : std::min(std::abs(z0), std::abs(z1)); }

  void Road() {
    for (float z0 = -kStreetHalfLength; z0 < kStreetHalfLength; z0 += 10.f) {
      const float ppm = NearestAbs(z0, z0 + 10) < 25.f ? 64.f : 32.f;
      const std::string name = "road_" + std::to_string(int(z0));
      int tex = -1;
      const int mat = Material(name, PaintRoad(rng_.Fork(), z0, 10.f, ppm), &tex);
      MeshData m;
      // Seen from above: u along +x, v along +z, normal +y.
      AddQuad(m, Vector3f(-kRoadHalfWidth, 0, z0), Vector3f(2 * kRoadHalfWidth, 0, 0), Vector3f(0, 0, 10.f));
      MeshData puddles = Puddles(wet_rng_, -kRoadHalfWidth, z0, kRoadHalfWidth, z0 + 10.f, 0.f, float(wet_));
      if (puddles.indices.empty()) {
        b_.AddNode(name, "road", std::move(m), mat);
        continue;
      }
      // The puddles are part of their road segment: its class and instance, its asphalt beneath.
      std::vector<MeshPart> parts;
      parts.push_back({std::move(m), mat});
      parts.push_back({std::move(puddles), PuddleMaterial(b_, name + "_puddles", tex)});
      b_.AddNode(name, "road", std::move(parts));
    }
  }

  void Sidewalks() {
    const float width = kFacadeX - kRoadHalfWidth;
    for (int side = -1; side <= 1; side += 2) {
      for (float z0 = -kStreetHalfLength; z0 < kStreetHalfLength; z0 += 10.f) {
        const float ppm = NearestAbs(z0, z0 + 10) < 25.f ? 64.f : 32.f;
        const std::string name = std::string(side < 0 ? "sidewalk_left_" : "sidewalk_right_") + std::to_string(int(z0));
        const int mat = Material(name, PaintSidewalk(rng_.Fork(), 10.f, ppm));
        MeshData m;
        const float curb = side * kRoadHalfWidth;
        // Top: u from the curb outwards (texture column 0 = curb stones), v along +z.
        if (side > 0) {
          AddQuad(m, Vector3f(curb, kCurbHeight, z0), Vector3f(width, 0, 0), Vector3f(0, 0, 10.f));
        } else {
          AddQuad(m, Vector3f(curb, kCurbHeight, z0 + 10.f), Vector3f(-width, 0, 0), Vector3f(0, 0, -10.f), {0, 1, 1, 0});
        }
        // Curb face towards the road, showing the curb-stone column of the texture.
        const UvRect curb_uv{0, 0, 0.05f, 1};
        if (side > 0) {
          AddQuad(m, Vector3f(curb, kCurbHeight, z0), Vector3f(0, 0, 10.f), Vector3f(0, -kCurbHeight, 0), curb_uv);
        } else {
          AddQuad(m, Vector3f(curb, kCurbHeight, z0 + 10.f), Vector3f(0, 0, -10.f), Vector3f(0, -kCurbHeight, 0), curb_uv);
        }
        b_.AddNode(name, "sidewalk", std::move(m), mat);
      }
    }
  }

  // One building as a box whose street-facing side carries its own facade texture.
  // `front_x` is the facade plane, `side` = +1 for the right (+x) side of the street.
  void Building(const std::string& name, int side, float front_x, float z0, float z1, float height) {
    const float ppm = PpmAt(NearestAbs(z0, z1));
    const float width = z1 - z0;
    std::vector<Pane> panes;
    const Canvas painted = PaintFacade(rng_.Fork(), width, height, ppm, glass_ ? &panes : nullptr);
    int facade_tex = -1;
    const int facade = Material(name + "_facade", painted, &facade_tex);
    const uint64_t sides_seed = rng_.Fork();
    const Vector3f sides_color = RandomColor(rng_, 0.4f, 0.8f);
    const int sides = Material(name + "_sides", PaintPlain(sides_seed, 256, 256, sides_color, 0.08f, 30));
    const float depth = 10.f;
    MeshData front, rest;
    // The facade quad: at x = front_x facing -x (right = +z), or at x = -front_x facing +x (right = -z).
    const Vector3f tl = side > 0 ? Vector3f(front_x, height, z0) : Vector3f(-front_x, height, z1);
    const Vector3f right(0, 0, side > 0 ? width : -width), down(0, -height, 0);
    AddQuad(front, tl, right, down);
    if (side > 0) {
      AddBox(rest, Vector3f(front_x + 0.001f, 0, z0), Vector3f(front_x + depth, height, z1));
    } else {
      AddBox(rest, Vector3f(-front_x - depth, 0, z0), Vector3f(-front_x - 0.001f, height, z1));
    }
    // One node (one instance) with two primitives, the facade and the plain body behind it, and
    // the windows' glass when the street has it.
    std::vector<MeshPart> parts;
    parts.push_back({std::move(front), facade});
    parts.push_back({std::move(rest), sides});
    AddFacadeNode(name, std::move(parts), tl, right, down, painted, facade_tex, panes);
  }

  void Buildings() {
    for (int side = -1; side <= 1; side += 2) {
      // Slots of random width along the street; one interior slot is an alley closed by a wall.
      std::vector<std::pair<float, float>> slots;
      for (float z = -kStreetHalfLength; z < kStreetHalfLength - 0.5f;) {
        float w = rng_.Uniform(8.f, 16.f);
        if (kStreetHalfLength - (z + w) < 6.f) w = kStreetHalfLength - z;
        slots.emplace_back(z, z + w);
        z += w;
      }
      const int alley = rng_.Int(1, int(slots.size()) - 2);
      for (size_t i = 0; i < slots.size(); ++i) {
        const auto [z0, z1] = slots[i];
        const std::string name = std::string(side < 0 ? "building_left_" : "building_right_") + std::to_string(i);
        if (int(i) == alley) {
          Building(name + "_rear", side, kFacadeX + 8.f, z0, z1, rng_.Uniform(10.f, 16.f));
          Wall(name + "_wall", side, z0, z1);
        } else {
          Building(name, side, kFacadeX, z0, z1, rng_.Uniform(8.f, 18.f));
        }
      }
    }
  }

  void Wall(const std::string& name, int side, float z0, float z1) {
    const float h = 2.4f, t = 0.3f, len = z1 - z0;
    const float ppm = PpmAt(NearestAbs(z0, z1));
    Canvas c(int(len * ppm), int(h * ppm), RandomColor(rng_, 0.45f, 0.65f));
    Rng rng(rng_.Fork());
    AddNoise(c, rng.Fork(), 0.1f, 32);
    for (float x = 0; x < c.w; x += 2.f * ppm) Stroke(c, x, 0, x, float(c.h), 2, Vector3f(0.2f, 0.2f, 0.2f));  // panel joints
    for (int i = 0, n = rng.Int(2, 4); i < n; ++i) {
      const float gx = rng.Uniform(0, float(c.w)), gy = rng.Uniform(0.3f, 0.7f) * c.h, gs = rng.Uniform(0.6f, 1.2f) * ppm;
      Graffiti(c, rng, gx, gy, gs);
    }
    const int mat = Material(name, c);
    MeshData m;
    const float x0 = side * kFacadeX;
    AddBox(m, Vector3f(std::min(x0, x0 + side * t), 0, z0), Vector3f(std::max(x0, x0 + side * t), h, z1));
    b_.AddNode(name, "wall", std::move(m), mat);
  }

  void EndBuildings() {
    for (int end = -1; end <= 1; end += 2) {
      const std::string name = end < 0 ? "building_end_south" : "building_end_north";
      const float height = rng_.Uniform(12.f, 18.f), width = 2 * kFacadeX;
      std::vector<Pane> panes;
      const Canvas painted = PaintFacade(rng_.Fork(), width, height, kFarPpm, glass_ ? &panes : nullptr);
      int facade_tex = -1;
      const int facade = Material(name + "_facade", painted, &facade_tex);
      MeshData front;
      const float z = end * kStreetHalfLength;
      // At +z facing -z (right = -x), or at -z facing +z (right = +x).
      const Vector3f tl(end > 0 ? kFacadeX : -kFacadeX, height, z), right(end > 0 ? -width : width, 0, 0), down(0, -height, 0);
      AddQuad(front, tl, right, down);
      if (panes.empty()) {
        b_.AddNode(name, "building", std::move(front), facade);
        continue;
      }
      std::vector<MeshPart> parts;
      parts.push_back({std::move(front), facade});
      AddFacadeNode(name, std::move(parts), tl, right, down, painted, facade_tex, panes);
    }
  }

  void Lamps() {
    const int mat = Material("lamp_metal", PaintPlain(rng_.Fork(), 64, 512, Vector3f(0.3f, 0.32f, 0.3f), 0.08f, 40));
    int k = 0;
    for (float z = -52.f; z <= 52.f; z += 13.f, ++k) {
      const int side = (k % 2) ? 1 : -1;
      MeshData m;
      AddCylinder(m, Vector3f(0, 0, 0), 0.09f, 6.f, 10);
      AddBox(m, Vector3f(-1.2f, 5.85f, -0.05f), Vector3f(0, 5.95f, 0.05f));  // arm over the road
      AddBox(m, Vector3f(-1.5f, 5.75f, -0.15f), Vector3f(-1.0f, 5.95f, 0.15f));  // lamp head
      b_.AddNode("lamp_" + std::to_string(k), "pole", std::move(m), mat, Placement(side * (kRoadHalfWidth + 0.4f), z, side > 0 ? 0.f : kPi));
    }
  }

  void Signs() {
    const int pole_mat = Material("sign_pole", PaintPlain(rng_.Fork(), 32, 256, Vector3f(0.55f, 0.57f, 0.6f), 0.06f, 10));
    const float zs[] = {-30.f, -11.f, 14.f, 33.f};
    for (int i = 0; i < 4; ++i) {
      const int side = (i % 2) ? -1 : 1;
      Rng rng(rng_.Fork());
      // Sign face: a red-bordered disc, a blue square or a warning triangle, with a glyph.
      Canvas c(128, 128, Vector3f(0.8f, 0.8f, 0.8f));
      const int kind = rng.Int(0, 2);
      if (kind == 0) {
        FillEllipse(c, 64, 64, 62, 62, Vector3f(0.8f, 0.05f, 0.05f));
        FillEllipse(c, 64, 64, 48, 48, Vector3f(0.95f, 0.95f, 0.95f));
      } else if (kind == 1) {
        FillRect(c, 2, 2, 126, 126, Vector3f(0.1f, 0.25f, 0.7f));
        FillRect(c, 10, 10, 118, 118, Vector3f(0.15f, 0.35f, 0.8f));
      } else {
        for (int y = 4; y < 124; ++y) {
          const float half = (y - 4) * 0.52f;
          for (int x = int(64 - half); x <= int(64 + half); ++x) c.Blend(x, y, (half - std::abs(x - 64.f) < 9 || y > 114) ? Vector3f(0.8f, 0.05f, 0.05f) : Vector3f(0.97f, 0.9f, 0.2f), 1);
        }
      }
      Glyphs(c, rng, 40, 44, 36, 2, Vector3f(0.05f, 0.05f, 0.05f));
      AddNoise(c, rng.Fork(), 0.04f, 16);
      const int face = Material("traffic_sign_" + std::to_string(i), c);
      MeshData pole, plate;
      AddCylinder(pole, Vector3f(0, 0, 0), 0.04f, 2.9f, 8);
      AddBox(plate, Vector3f(-0.35f, 2.2f, -0.12f), Vector3f(0.35f, 2.9f, -0.09f));
      const Eigen::Matrix4d place = Placement(side * (kRoadHalfWidth + 0.5f), zs[i], rng.Uniform(-0.3f, 0.3f) + (side > 0 ? 0.f : kPi));
      b_.AddNode("sign_pole_" + std::to_string(i), "pole", std::move(pole), pole_mat, place);
      b_.AddNode("traffic_sign_" + std::to_string(i), "traffic sign", std::move(plate), face, place);
    }
  }

  void Railing() {
    const int mat = Material("railing", PaintPlain(rng_.Fork(), 64, 64, Vector3f(0.2f, 0.3f, 0.25f), 0.1f, 8));
    MeshData m;
    for (float z = 0; z <= 6.01f; z += 1.5f) AddBox(m, Vector3f(-0.03f, 0, z - 0.03f), Vector3f(0.03f, 1.0f, z + 0.03f));
    AddBox(m, Vector3f(-0.025f, 0.95f, 0), Vector3f(0.025f, 1.0f, 6.f));
    AddBox(m, Vector3f(-0.025f, 0.5f, 0), Vector3f(0.025f, 0.54f, 6.f));
    b_.AddNode("fence_0", "fence", std::move(m), mat, Placement(-(kRoadHalfWidth + 0.25f), 3.f, 0.f) * Eigen::Affine3d(Eigen::Translation3d(0, kCurbHeight, 0)).matrix());
  }

  void Cars() {
    const float zs[] = {-38.f, -21.f, -9.f, 11.5f, 24.f, 41.f};
    for (int i = 0; i < 5; ++i) {
      Rng rng(rng_.Fork());
      const int side = (i % 2) ? -1 : 1;
      const float z = zs[i + (i >= 3 ? 1 : 0)] + rng.Uniform(-1.5f, 1.5f);
      // Atlas: top half cabin (windows), bottom-left body paint, bottom-right tyres.
      const Vector3f paint = RandomColor(rng, 0.05f, 0.9f);
      Canvas c(256, 256, paint);
      FillRect(c, 0, 0, 256, 128, Vector3f(0.1f, 0.12f, 0.15f));
      for (int k = 0; k < 4; ++k) FillRect(c, 8 + k * 62.f, 10, 60 + k * 62.f, 118, Vector3f(0.2f, 0.25f, 0.3f));  // window panes
      FillRect(c, 192, 128, 256, 256, Vector3f(0.05f, 0.05f, 0.05f));
      FillEllipse(c, 224, 192, 20, 20, Vector3f(0.6f, 0.6f, 0.6f));  // hub
      FillRect(c, 10, 150, 40, 165, Vector3f(0.95f, 0.9f, 0.6f));    // lights
      FillRect(c, 150, 150, 180, 165, Vector3f(0.8f, 0.1f, 0.1f));
      FillRect(c, 70, 200, 120, 215, Vector3f(0.9f, 0.9f, 0.9f));    // number plate
      Glyphs(c, rng, 72, 202, 11, 5, Vector3f(0.05f, 0.05f, 0.05f));
      AddNoise(c, rng.Fork(), 0.05f, 32);
      const int mat = Material("car_" + std::to_string(i), c);
      MeshData m;
      const UvRect body{0, 0.5f, 0.75f, 1}, cabin{0, 0, 1, 0.5f}, tyre{0.75f, 0.5f, 1, 1};
      const float len = rng.Uniform(3.8f, 4.6f), wid = rng.Uniform(1.7f, 1.9f);
      AddBox(m, Vector3f(-wid / 2, 0.3f, -len / 2), Vector3f(wid / 2, 1.0f, len / 2), body);
      AddBox(m, Vector3f(-wid / 2 + 0.1f, 1.0f, -len / 2 + 0.7f), Vector3f(wid / 2 - 0.1f, rng.Uniform(1.45f, 1.7f), len / 2 - 1.0f), cabin);
      for (int wx = -1; wx <= 1; wx += 2) {
        for (int wz = -1; wz <= 1; wz += 2) {
          AddBox(m, Vector3f(wx * wid / 2 - 0.12f, 0, wz * (len / 2 - 0.75f) - 0.33f), Vector3f(wx * wid / 2 + 0.12f, 0.66f, wz * (len / 2 - 0.75f) + 0.33f), tyre);
        }
      }
      float yaw = rng.Uniform(-0.05f, 0.05f);
      if (rng.Chance(0.5f)) yaw += kPi;
      const Eigen::Matrix4d place = Placement(side * (kRoadHalfWidth - 1.1f), z, yaw);
      cars_.push_back({b_.AddNode("car_" + std::to_string(i), "car", std::move(m), mat, place), place, yaw});
    }
  }

  void People() {
    const float spots[][2] = {{6.5f, -16.f}, {-7.2f, -5.5f}, {7.6f, 7.f}, {-6.3f, 19.f}};
    for (int i = 0; i < 4; ++i) {
      Rng rng(rng_.Fork());
      // Atlas: top half shirt, bottom-left trousers, bottom-right skin/hair.
      Canvas c(128, 128, RandomColor(rng, 0.1f, 0.9f));
      FillRect(c, 0, 64, 96, 128, RandomColor(rng, 0.05f, 0.5f));
      const float sr = rng.Uniform(0.4f, 0.9f), sg = rng.Uniform(0.3f, 0.7f), sb = rng.Uniform(0.2f, 0.5f);
      FillRect(c, 96, 64, 128, 128, Vector3f(sr, sg, sb));
      for (int k = 0; k < 6; ++k) {  // print pattern on the shirt
        const float ex = rng.Uniform(0, 128), ey = rng.Uniform(0, 60), rx = rng.Uniform(3, 10), ry = rng.Uniform(3, 10);
        FillEllipse(c, ex, ey, rx, ry, RandomColor(rng), 0.8f);
      }
      AddNoise(c, rng.Fork(), 0.05f, 16);
      const int mat = Material("person_" + std::to_string(i), c);
      const float s = rng.Uniform(0.9f, 1.08f);  // body scale
      MeshData m = PersonMesh(s, rng.Fork());
      const float yaw = rng.Uniform(0, 2 * kPi);
      Eigen::Matrix4d place = Placement(spots[i][0], spots[i][1], yaw);
      place(1, 3) = kCurbHeight;  // standing on the sidewalk
      people_.push_back({b_.AddNode("person_" + std::to_string(i), "person", std::move(m), mat, place), place, yaw});
    }
  }

  void Trees() {
    const float spots[][2] = {{-7.5f, -27.f}, {7.5f, -34.f}, {-7.5f, 27.f}, {7.5f, 21.f}};
    for (int i = 0; i < 4; ++i) {
      Rng rng(rng_.Fork());
      // Atlas: left quarter bark, the rest leaves.
      Canvas c(256, 256, Vector3f(0.16f, 0.32f, 0.1f));
      FillRect(c, 0, 0, 64, 256, Vector3f(0.3f, 0.22f, 0.15f));
      AddNoise(c, rng.Fork(), 0.1f, 32, 0.05f);
      for (int k = 0; k < 400; ++k) {
        const float x = rng.Uniform(64, 256), y = rng.Uniform(0, 256), r = rng.Uniform(1.5f, 5.f);
        const float lr = rng.Uniform(0.1f, 0.4f), lg = rng.Uniform(0.25f, 0.55f), lb = rng.Uniform(0.05f, 0.2f);
        FillEllipse(c, x, y, r, r * 0.6f, Vector3f(lr, lg, lb), 0.8f);
      }
      const int mat = Material("tree_" + std::to_string(i), c);
      const UvRect bark{0, 0, 0.25f, 1}, leaves{0.25f, 0, 1, 1};
      MeshData m;
      const float trunk_h = rng.Uniform(2.8f, 3.6f);
      AddCylinder(m, Vector3f(0, 0, 0), 0.15f, trunk_h + 0.5f, 9, bark);
      for (int k = 0, n = rng.Int(3, 5); k < n; ++k) {
        const float r = rng.Uniform(1.1f, 1.7f);
        const float cx = rng.Uniform(-0.7f, 0.7f), cy = trunk_h + rng.Uniform(0.6f, 1.8f), cz = rng.Uniform(-0.7f, 0.7f);
        AddBlob(m, Vector3f(cx, cy, cz), Vector3f(r, r * 0.85f, r), 0.35f, rng.Fork(), leaves);
      }
      const float yaw = rng.Uniform(0, 2 * kPi);
      Eigen::Matrix4d place = Placement(spots[i][0], spots[i][1], yaw);
      place(1, 3) = kCurbHeight;
      trees_.push_back({b_.AddNode("tree_" + std::to_string(i), "vegetation", std::move(m), mat, place), place, yaw});
    }
  }

  // Trees sway in one wind; people pace along their sidewalk in the direction (+-z) they face
  // most; cars drive the two lanes (+z at x = -2, -z at x = +2) at `traffic` vehicles per 100 m,
  // the parked cars first, then more, each lane's ends 4 m behind the end facades.
  void Animate(double traffic) {
    const Eigen::Vector3f wind = RandomWind(motion_rng_);
    std::vector<Obstacle> trunks;
    for (const Placed& t : trees_) {
      AddMotion(&b_, t.node, SwayKeys(RandomSway(t.yaw, wind, motion_rng_)));
      trunks.push_back({float(t.place(0, 3)), float(t.place(2, 3)), 0.3f});
    }
    for (const Placed& p : people_) {
      Walk w;
      w.start = p.place.topRightCorner<3, 1>().cast<float>();
      w.yaw = p.place(2, 2) >= 0 ? 0.f : kPi;
      w.leg_m = ClearLength({w.start.x(), w.start.z()}, {0.f, p.place(2, 2) >= 0 ? 1.f : -1.f}, 12.f, 0.4f, trunks, kFacadeX,
                            kStreetHalfLength - 5.f);
      w.speed_mps = motion_rng_.Uniform(1.2f, 1.5f);
      w.phase = motion_rng_.Uniform();
      if (w.leg_m >= 1.f) AddMotion(&b_, p.node, WalkKeys(w));
    }
    const float end = kStreetHalfLength + 4.f;
    std::vector<LaneDrive> lanes(2);
    lanes[0].from = Vector3f(-2.f, 0, -end);
    lanes[0].to = Vector3f(-2.f, 0, end);
    lanes[1].from = Vector3f(2.f, 0, end);
    lanes[1].to = Vector3f(2.f, 0, -end);
    for (LaneDrive& lane : lanes) lane.offset_m = motion_rng_.Uniform(0, 2 * end);
    const std::vector<LaneDrive> drives = SpreadOnLanes(VehiclesOnLanes(traffic, 2 * 2 * kStreetHalfLength), lanes);
    std::vector<int> extra_paint;  // three more car models for the cars beyond the parked ones
    for (size_t k = 0; k < drives.size(); ++k) {
      int node = k < cars_.size() ? cars_[k].node : -1;
      if (node < 0) {
        const size_t extra = k - cars_.size();
        if (extra < 3) {
          const Vector3f paint = RandomColor(motion_rng_, 0.05f, 0.9f);
          extra_paint.push_back(Material("car_traffic_paint_" + std::to_string(extra_paint.size()), PaintCarAtlas(motion_rng_.Fork(), paint)));
        }
        node = b_.AddNode("car_traffic_" + std::to_string(k), "car", CarMesh(4.3f, 1.8f, 1.55f), extra_paint[extra % 3],
                          Placement(drives[k].from.x(), drives[k].from.z(), 0));
      }
      AddMotion(&b_, node, LaneDriveKeys(drives[k]));
    }
  }

  struct Placed {
    int node;
    Eigen::Matrix4d place;
    float yaw;
  };
  std::vector<Placed> cars_, people_, trees_;
  Rng rng_;
  Rng motion_rng_;
  Rng wet_rng_;
  bool glass_;   // glass in the windows
  double wet_;   // the share of the road the puddles cover
  SceneBuilder b_;
};

}  // namespace

std::vector<uint8_t> StreetSceneGlb(uint64_t seed) { return StreetGenerator(seed, false, 0.0).Build().ToGlb(); }

std::vector<uint8_t> StreetSceneGlb(uint64_t seed, bool animated, double traffic, bool glass, double wet) {
  return StreetGenerator(seed, glass, wet).Build(animated, traffic).ToGlb();
}

void WriteStreetScene(const std::filesystem::path& glb_path, uint64_t seed) {
  StreetGenerator(seed, false, 0.0).Build().WriteGlb(glb_path);
}

}  // namespace rigsim
