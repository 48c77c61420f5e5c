#include "procedural/glass_and_water.h"

#include <algorithm>
#include <cmath>

#include "procedural/objects.h"

namespace rigsim::procedural {

int GlassMaterial(SceneBuilder& builder, const std::string& name, int texture) {
  const int m = builder.AddMaterial(name, Eigen::Vector4f(kWindowGlassShade, kWindowGlassShade, kWindowGlassShade, 1.f), texture);
  builder.SetMetallicRoughness(m, 0.f, kWindowGlassRoughness);
  return m;
}

int PuddleMaterial(SceneBuilder& builder, const std::string& name, int texture) {
  const int m = builder.AddMaterial(name, Eigen::Vector4f(kPuddleShade, kPuddleShade, kPuddleShade, 1.f), texture);
  builder.SetMetallicRoughness(m, 0.f, kPuddleRoughness);
  return m;
}

MeshData GlassPanes(const Eigen::Vector3f& top_left, const Eigen::Vector3f& right, const Eigen::Vector3f& down, int w, int h,
                    const std::vector<Pane>& panes) {
  MeshData m;
  const Vector3f front = right.cross(-down).normalized();
  for (const Pane& p : panes) {
    // Clamped to the texture: a pane painted past the canvas edge has no facade behind it there.
    const float u0 = std::clamp(p.x0 / float(w), 0.f, 1.f), u1 = std::clamp(p.x1 / float(w), 0.f, 1.f);
    const float v0 = std::clamp(p.y0 / float(h), 0.f, 1.f), v1 = std::clamp(p.y1 / float(h), 0.f, 1.f);
    if (!(u1 > u0) || !(v1 > v0)) continue;
    AddQuad(m, top_left + u0 * right + v0 * down + kWindowGlassOffsetM * front, (u1 - u0) * right, (v1 - v0) * down, {u0, v0, u1, v1});
  }
  return m;
}

MeshData Puddles(Rng& rng, float x0, float z0, float x1, float z1, float y, float wet) {
  MeshData m;
  if (!(wet > 0)) return m;
  constexpr float kMargin = 0.2f;
  constexpr int kRim = 20;          // outline vertices
  constexpr float kMaxWobble = 1.3f;  // the outline's largest radius over the ellipse's
  const float target = wet * (x1 - x0) * (z1 - z0);
  struct Box {  // a puddle's extent: centre and half sizes
    float x, z, hx, hz;
  };
  std::vector<Box> placed;
  float area = 0;
  for (int attempt = 0; attempt < 600 && area < target; ++attempt) {
    // Smaller puddles once the large ones have found their places, to fill the gaps between them.
    const float size = attempt < 200 ? 1.f : attempt < 400 ? 0.6f : 0.35f;
    const float rx = size * rng.Uniform(0.3f, 1.0f);
    const float stretch = rng.Uniform(1.f, 2.f);
    const float rz = rx * stretch;
    const float reach_x = kMaxWobble * rx, reach_z = kMaxWobble * rz;
    if (x1 - x0 < 2 * (reach_x + kMargin) || z1 - z0 < 2 * (reach_z + kMargin)) continue;
    const float cx = rng.Uniform(x0 + kMargin + reach_x, x1 - kMargin - reach_x);
    const float cz = rng.Uniform(z0 + kMargin + reach_z, z1 - kMargin - reach_z);
    const float p1 = rng.Uniform(0, 2 * kPi), p2 = rng.Uniform(0, 2 * kPi);
    const float p3 = rng.Uniform(0, 2 * kPi);
    const Box box{cx, cz, reach_x, reach_z};
    const bool overlaps = std::any_of(placed.begin(), placed.end(), [&](const Box& o) {
      return std::abs(o.x - box.x) < o.hx + box.hx && std::abs(o.z - box.z) < o.hz + box.hz;
    });
    if (overlaps) continue;
    placed.push_back(box);
    // A fan from the centre; the rim's radius wobbles by three harmonics of random phase.
    auto vertex = [&](float x, float z) {
      m.positions.emplace_back(x, y + kPuddleHeightM, z);
      m.normals.emplace_back(0.f, 1.f, 0.f);
      m.texcoords.emplace_back((x - x0) / (x1 - x0), (z - z0) / (z1 - z0));
    };
    const uint32_t centre = uint32_t(m.positions.size());
    vertex(cx, cz);
    float rim_x[kRim], rim_z[kRim];
    for (int k = 0; k < kRim; ++k) {
      const float a = 2 * kPi * float(k) / kRim;
      const float wobble = 1.f + 0.15f * std::sin(2 * a + p1) + 0.1f * std::sin(3 * a + p2) + 0.05f * std::sin(5 * a + p3);
      rim_x[k] = cx + wobble * rx * std::cos(a);
      rim_z[k] = cz + wobble * rz * std::sin(a);
      vertex(rim_x[k], rim_z[k]);
    }
    for (int k = 0; k < kRim; ++k) {
      const int next = (k + 1) % kRim;
      // Counter-clockwise seen from above (+y): the rim's next vertex first.
      m.indices.insert(m.indices.end(), {centre, centre + 1 + uint32_t(next), centre + 1 + uint32_t(k)});
      area += 0.5f * std::abs((rim_x[k] - cx) * (rim_z[next] - cz) - (rim_x[next] - cx) * (rim_z[k] - cz));
    }
  }
  return m;
}

float GroundArea(const MeshData& mesh) {
  double area = 0;
  for (size_t i = 0; i + 2 < mesh.indices.size(); i += 3) {
    const Vector3f& a = mesh.positions[mesh.indices[i]];
    const Vector3f& b = mesh.positions[mesh.indices[i + 1]];
    const Vector3f& c = mesh.positions[mesh.indices[i + 2]];
    const Vector3f ab = b - a, ac = c - a;
    area += 0.5 * std::abs(double(ab.z()) * ac.x() - double(ab.x()) * ac.z());
  }
  return float(area);
}

}  // namespace rigsim::procedural
