#include "procedural/objects.h"

#include <cmath>

#include <Eigen/Geometry>

#include "procedural/textures.h"

namespace rigsim::procedural {
// ---------------------------------------------------------------------------------------------
// Geometry helpers. Quads are given by their top-left corner and the full right and down edges
// as seen from the front; the front normal is right x up, triangles counter-clockwise from it.



void AddQuad(MeshData& m, const Vector3f& tl, const Vector3f& right, const Vector3f& down, const UvRect& uv) {
  const uint32_t b = uint32_t(m.positions.size());
  const Vector3f n = right.cross(-down).normalized();
  m.positions.insert(m.positions.end(), {tl, tl + right, tl + down, tl + right + down});
  m.normals.insert(m.normals.end(), {n, n, n, n});
  m.texcoords.insert(m.texcoords.end(), {Vector2f(uv.u0, uv.v0), Vector2f(uv.u1, uv.v0), Vector2f(uv.u0, uv.v1), Vector2f(uv.u1, uv.v1)});
  m.indices.insert(m.indices.end(), {b, b + 2, b + 3, b, b + 3, b + 1});
}

// Axis-aligned box; every face shows `uv` of the texture.
void AddBox(MeshData& m, const Vector3f& lo, const Vector3f& hi, const UvRect& uv) {
  const Vector3f d = hi - lo;
  AddQuad(m, Vector3f(hi.x(), hi.y(), hi.z()), Vector3f(0, 0, -d.z()), Vector3f(0, -d.y(), 0), uv);  // +x
  AddQuad(m, Vector3f(lo.x(), hi.y(), lo.z()), Vector3f(0, 0, d.z()), Vector3f(0, -d.y(), 0), uv);   // -x
  AddQuad(m, Vector3f(lo.x(), hi.y(), hi.z()), Vector3f(d.x(), 0, 0), Vector3f(0, -d.y(), 0), uv);   // +z
  AddQuad(m, Vector3f(hi.x(), hi.y(), lo.z()), Vector3f(-d.x(), 0, 0), Vector3f(0, -d.y(), 0), uv);  // -z
  AddQuad(m, Vector3f(lo.x(), hi.y(), lo.z()), Vector3f(d.x(), 0, 0), Vector3f(0, 0, d.z()), uv);    // +y
  AddQuad(m, Vector3f(lo.x(), lo.y(), hi.z()), Vector3f(d.x(), 0, 0), Vector3f(0, 0, -d.z()), uv);   // -y
}

// Vertical cylinder (with a top cap) standing on `base`.
void AddCylinder(MeshData& m, const Vector3f& base, float radius, float height, int segments, const UvRect& uv) {
  for (int i = 0; i < segments; ++i) {
    const float a0 = 2 * kPi * i / segments, a1 = 2 * kPi * (i + 1) / segments;
    const Vector3f p0 = base + Vector3f(radius * std::sin(a0), height, radius * std::cos(a0));
    const Vector3f p1 = base + Vector3f(radius * std::sin(a1), height, radius * std::cos(a1));
    const float u0 = uv.u0 + (uv.u1 - uv.u0) * i / segments, u1 = uv.u0 + (uv.u1 - uv.u0) * (i + 1) / segments;
    AddQuad(m, p0, p1 - p0, Vector3f(0, -height, 0), {u0, uv.v0, u1, uv.v1});
    const uint32_t b = uint32_t(m.positions.size());
    const Vector3f top = base + Vector3f(0, height, 0);
    m.positions.insert(m.positions.end(), {top, p0, p1});
    m.normals.insert(m.normals.end(), 3, Vector3f(0, 1, 0));
    m.texcoords.insert(m.texcoords.end(), {Vector2f(uv.u0, uv.v0), Vector2f(u0, uv.v0), Vector2f(u1, uv.v0)});
    m.indices.insert(m.indices.end(), {b, b + 1, b + 2});
  }
}

// Sphere-like blob with radial noise (tree crowns, heads).
void AddBlob(MeshData& m, const Vector3f& centre, const Vector3f& radii, float bumpiness, uint64_t seed, const UvRect& uv) {
  const int stacks = 10, slices = 16;
  const uint32_t b = uint32_t(m.positions.size());
  for (int i = 0; i <= stacks; ++i) {
    const float th = kPi * i / stacks;
    for (int j = 0; j <= slices; ++j) {
      const float ph = 2 * kPi * j / slices;
      const Vector3f dir(std::sin(th) * std::sin(ph), std::cos(th), std::sin(th) * std::cos(ph));
      const float r = 1.f + bumpiness * (ValueNoise(float(j % slices) * 0.7f, float(i) * 0.7f, seed) - 0.5f);
      m.positions.push_back(centre + r * dir.cwiseProduct(radii));
      m.normals.push_back(dir);
      m.texcoords.emplace_back(uv.u0 + (uv.u1 - uv.u0) * j / slices, uv.v0 + (uv.v1 - uv.v0) * i / stacks);
    }
  }
  for (int i = 0; i < stacks; ++i) {
    for (int j = 0; j < slices; ++j) {
      const uint32_t tl = b + i * (slices + 1) + j, tr = tl + 1, bl = tl + slices + 1, br = bl + 1;
      if (i > 0) m.indices.insert(m.indices.end(), {tl, bl, br});
      if (i < stacks - 1) m.indices.insert(m.indices.end(), {tl, br, tr});
    }
  }
}

Eigen::Matrix4d Placement(float x, float z, float yaw) {
  Eigen::Affine3d t = Eigen::Affine3d::Identity();
  t.translate(Eigen::Vector3d(x, 0, z));
  t.rotate(Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitY()));
  return t.matrix();
}

}  // namespace rigsim::procedural

namespace rigsim::procedural {

MeshData CarMesh(float len, float wid, float cabin_height) {
  MeshData m;
  const UvRect body{0, 0.5f, 0.75f, 1}, cabin{0, 0, 1, 0.5f}, tyre{0.75f, 0.5f, 1, 1};
  AddBox(m, Vector3f(-wid / 2, 0.3f, -len / 2), Vector3f(wid / 2, 1.0f, len / 2), body);
  AddBox(m, Vector3f(-wid / 2 + 0.1f, 1.0f, -len / 2 + 0.7f), Vector3f(wid / 2 - 0.1f, cabin_height, len / 2 - 1.0f), cabin);
  for (int wx = -1; wx <= 1; wx += 2) {
    for (int wz = -1; wz <= 1; wz += 2) {
      AddBox(m, Vector3f(wx * wid / 2 - 0.12f, 0, wz * (len / 2 - 0.75f) - 0.33f),
             Vector3f(wx * wid / 2 + 0.12f, 0.66f, wz * (len / 2 - 0.75f) + 0.33f), tyre);
    }
  }
  return m;
}

std::vector<MeshPart> BusParts(float len, float wid, float height, int body_material, int poster_material) {
  MeshData body, sides;
  AddBox(body, Vector3f(-wid / 2 + 0.01f, 0.35f, -len / 2), Vector3f(wid / 2 - 0.01f, height, len / 2));
  for (int wz = -1; wz <= 1; wz += 2) {
    AddBox(body, Vector3f(-wid / 2 - 0.05f, 0, wz * len * 0.3f - 0.5f), Vector3f(wid / 2 + 0.05f, 1.0f, wz * len * 0.3f + 0.5f));
  }
  // Poster on both long sides, seen the right way round from outside.
  AddQuad(sides, Vector3f(wid / 2, height - 0.2f, len / 2 - 0.3f), Vector3f(0, 0, -(len - 0.6f)), Vector3f(0, -(height - 0.8f), 0));
  AddQuad(sides, Vector3f(-wid / 2, height - 0.2f, -len / 2 + 0.3f), Vector3f(0, 0, len - 0.6f), Vector3f(0, -(height - 0.8f), 0));
  std::vector<MeshPart> parts;
  parts.push_back({std::move(body), body_material});
  parts.push_back({std::move(sides), poster_material});
  return parts;
}

MeshData PersonMesh(float s, uint64_t seed) {
  const UvRect shirt{0, 0, 1, 0.5f}, trousers{0, 0.5f, 0.75f, 1}, skin{0.75f, 0.5f, 1, 1};
  MeshData m;
  AddBox(m, s * Vector3f(-0.2f, 0, -0.1f), s * Vector3f(-0.03f, 0.85f, 0.1f), trousers);
  AddBox(m, s * Vector3f(0.03f, 0, -0.1f), s * Vector3f(0.2f, 0.85f, 0.1f), trousers);
  AddBox(m, s * Vector3f(-0.23f, 0.85f, -0.12f), s * Vector3f(0.23f, 1.5f, 0.12f), shirt);
  AddBox(m, s * Vector3f(-0.32f, 0.8f, -0.06f), s * Vector3f(-0.23f, 1.45f, 0.06f), shirt);
  AddBox(m, s * Vector3f(0.23f, 0.8f, -0.06f), s * Vector3f(0.32f, 1.45f, 0.06f), shirt);
  AddBlob(m, s * Vector3f(0, 1.63f, 0), s * Vector3f(0.1f, 0.12f, 0.11f), 0.05f, seed, skin);
  return m;
}

void AddCrossedCards(MeshData& m, const Vector3f& centre, float size, int count, float start_angle) {
  for (int i = 0; i < count; ++i) {
    const float a = start_angle + kPi * i / count;
    const Vector3f right(size * std::cos(a), 0, size * std::sin(a));
    AddQuad(m, centre - 0.5f * right + Vector3f(0, 0.5f * size, 0), right, Vector3f(0, -size, 0));
  }
}

}  // namespace rigsim::procedural
