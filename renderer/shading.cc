#include "renderer/shading.h"

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace rigsim {
namespace {

// dP/du and -dP/dv of the triangle p0..p2 with texture coordinates t0..t2 (zero when the
// coordinates are degenerate): the solution of p1 - p0 = dP/du du1 + dP/dv dv1 and likewise for p2.
TangentFrame TangentFrameOf(const Eigen::Vector3f& p0, const Eigen::Vector3f& p1, const Eigen::Vector3f& p2,
                            const Eigen::Vector2f& t0, const Eigen::Vector2f& t1, const Eigen::Vector2f& t2) {
  const Eigen::Vector3f e1 = p1 - p0, e2 = p2 - p0;
  const Eigen::Vector2f d1 = t1 - t0, d2 = t2 - t0;
  const float det = d1.x() * d2.y() - d2.x() * d1.y();
  if (!(std::abs(det) > 0.0f)) return {Eigen::Vector3f::Zero(), Eigen::Vector3f::Zero()};
  return {(e1 * d2.y() - e2 * d1.y()) / det, -(e2 * d1.x() - e1 * d2.x()) / det};
}

// The material's part of `m`: colour, alpha, emission and the texture layers the mesh has
// coordinates for.
void ApplyMaterial(const Material& material, const SceneMesh& mesh, const MaterialTextures& textures, MeshShading& m) {
  m.base_color = material.base_color_factor;
  if (material.base_color_texture >= 0 && !mesh.texcoords.empty()) {
    m.texture = &textures.colour[material.base_color_texture];
  }
  // A single-hit tracer cannot composite BLEND; cutting it out at the cutoff at least keeps
  // fully transparent texels (foliage cards, fences) from occluding.
  m.alpha_tested = material.alpha_mode != AlphaMode::kOpaque;
  m.alpha_cutoff = material.alpha_cutoff;
  m.unlit = material.unlit;
  m.gloss = GlossOf(material);
  m.metallic = material.metallic;
  m.emissive = material.emissive;
  m.emits = !material.unlit && material.emissive != Eigen::Vector3f::Zero();
  if (material.emissive_texture >= 0 && !mesh.emissive_texcoords.empty()) {
    m.emissive_layer.Build(&textures.colour[material.emissive_texture], mesh, mesh.emissive_texcoords);
  }
  if (material.occlusion_texture >= 0 && !mesh.occlusion_texcoords.empty() && !material.unlit) {
    m.occlusion_layer.Build(&textures.data.at(material.occlusion_texture), mesh, mesh.occlusion_texcoords);
    m.occlusion_strength = material.occlusion_strength;
  }
  if (material.normal_texture >= 0 && !mesh.normal_texcoords.empty() && !material.unlit) {
    m.normal_layer.Build(&textures.data.at(material.normal_texture), mesh, mesh.normal_texcoords);
    m.normal_scale = material.normal_scale;
    m.tangent_frames.resize(m.normal_layer.corners.size());
    for (size_t t = 0; t < m.tangent_frames.size(); ++t) {
      const uint32_t* tri = &mesh.indices[3 * t];
      const auto& c = m.normal_layer.corners[t];
      m.tangent_frames[t] =
          TangentFrameOf(mesh.positions[tri[0]], mesh.positions[tri[1]], mesh.positions[tri[2]], c[0], c[1], c[2]);
    }
  }
}

// The per-triangle part of `m`: face normals, texel densities and the corners' attributes.
void CopyTriangleAttributes(const SceneMesh& mesh, MeshShading& m) {
  const size_t num_tris = mesh.indices.size() / 3;
  m.triangles.assign(num_tris, {});
  if (m.texture != nullptr) m.corner_texcoords.resize(num_tris);
  bool smooth = false;  // some vertex normal differs from its face's: interpolate per hit
  for (size_t t = 0; t < num_tris; ++t) {
    const uint32_t* tri = &mesh.indices[3 * t];
    const Eigen::Vector3f& p0 = mesh.positions[tri[0]];
    const Eigen::Vector3f cross = (mesh.positions[tri[1]] - p0).cross(mesh.positions[tri[2]] - p0);
    const float area2 = cross.norm();
    m.triangles[t].face_normal = area2 > 0 ? Eigen::Vector3f(cross / area2) : Eigen::Vector3f::Zero();
    const Eigen::Vector3f& p1 = mesh.positions[tri[1]];
    const Eigen::Vector3f& p2 = mesh.positions[tri[2]];
    if (m.texture != nullptr) {
      const auto& tc = mesh.texcoords;
      m.triangles[t].texels_per_metre = TexelsPerMetre(p0, p1, p2, tc[tri[0]], tc[tri[1]], tc[tri[2]], m.texture->texel_scale);
      m.corner_texcoords[t] = {tc[tri[0]], tc[tri[1]], tc[tri[2]]};
    }
    for (int c = 0; c < 3 && !mesh.normals.empty() && !smooth; ++c) {
      const Eigen::Vector3f& vn = mesh.normals[tri[c]];
      const float len = vn.norm();
      smooth = !(len > 0 && std::abs(vn.dot(m.triangles[t].face_normal)) > (1.0f - 1e-6f) * len);
    }
  }
  if (!mesh.colors.empty()) {
    // glTF's default material is white: vertex colours on a mesh without one show as they are.
    if (mesh.material < 0) m.base_color = Eigen::Vector4f::Ones();
    m.corner_colors.resize(num_tris);
    for (size_t t = 0; t < num_tris; ++t) {
      const uint32_t* tri = &mesh.indices[3 * t];
      m.corner_colors[t] = {mesh.colors[tri[0]], mesh.colors[tri[1]], mesh.colors[tri[2]]};
    }
  }
  if (smooth) {
    m.corner_normals.resize(num_tris);
    for (size_t t = 0; t < num_tris; ++t) {
      const uint32_t* tri = &mesh.indices[3 * t];
      m.corner_normals[t] = {mesh.normals[tri[0]], mesh.normals[tri[1]], mesh.normals[tri[2]]};
    }
  }
}

}  // namespace

MaterialTextures BuildMaterialTextures(const Scene& scene) {
  MaterialTextures textures;
  textures.colour.reserve(scene.textures.size());
  for (const Texture& texture : scene.textures) {
    textures.colour.push_back(BuildMipTexture(texture, TexelEncoding::kSrgb));
  }
  // Normal and occlusion maps hold data, not colour: their levels are built from the codes as
  // they are.
  for (const Material& material : scene.materials) {
    for (const int t : {material.normal_texture, material.occlusion_texture}) {
      if (t >= 0 && size_t(t) < scene.textures.size() && !textures.data.count(t)) {
        textures.data.emplace(t, BuildMipTexture(scene.textures[t], TexelEncoding::kLinear));
      }
    }
  }
  return textures;
}

void TextureLayer::Build(const MipTexture* tex, const SceneMesh& mesh, const std::vector<Eigen::Vector2f>& texcoords) {
  texture = tex;
  const size_t num_tris = mesh.indices.size() / 3;
  corners.resize(num_tris);
  texels_per_metre.resize(num_tris);
  for (size_t t = 0; t < num_tris; ++t) {
    const uint32_t* tri = &mesh.indices[3 * t];
    corners[t] = {texcoords[tri[0]], texcoords[tri[1]], texcoords[tri[2]]};
    texels_per_metre[t] = TexelsPerMetre(mesh.positions[tri[0]], mesh.positions[tri[1]], mesh.positions[tri[2]],
                                         corners[t][0], corners[t][1], corners[t][2], texture->texel_scale);
  }
}

MeshShading PrepareMeshShading(const SceneMesh& mesh, const Scene& scene, const MaterialTextures& textures) {
  MeshShading m;
  m.class_id = mesh.class_id;
  m.instance_id = mesh.instance_id;
  if (mesh.material >= 0) ApplyMaterial(scene.materials[mesh.material], mesh, textures, m);
  CopyTriangleAttributes(mesh, m);
  return m;
}

MeshShading RotatedShading(const MeshShading& m, const Eigen::Matrix3f& rotation) {
  MeshShading out = m;
  for (MeshShading::TriangleShading& t : out.triangles) t.face_normal = rotation * t.face_normal;
  for (auto& corners : out.corner_normals) {
    for (Eigen::Vector3f& n : corners) n = rotation * n;
  }
  for (TangentFrame& f : out.tangent_frames) {
    f.along_u = rotation * f.along_u;
    f.up_image = rotation * f.up_image;
  }
  return out;
}

ShadeParams ShadeParamsOf(const RenderOptions& options) {
  ShadeParams shade;
  shade.sun_dir = options.sun_direction_world.normalized().cast<float>();
  shade.sun_intensity = float(options.sun_intensity);
  shade.sky_intensity = float(options.sky_intensity);
  shade.shadows = options.shadows;
  return shade;
}

Eigen::Vector3f NormalMapped(const MeshShading& m, const SampleRecord& r, const Eigen::Vector3f& ng,
                             const Eigen::Vector3f& n) {
  const Hit& hit = r.hit;
  const TangentFrame& frame = m.tangent_frames[hit.prim];
  Eigen::Vector3f x = frame.along_u - n * n.dot(frame.along_u);
  Eigen::Vector3f y = frame.up_image - n * n.dot(frame.up_image);
  if (!(x.squaredNorm() > 0.0f) || !(y.squaredNorm() > 0.0f)) return n;
  const Eigen::Vector3f outside = m.corner_normals.empty() ? m.triangles[hit.prim].face_normal
                                                           : AtHit(m.corner_normals[hit.prim], hit.u, hit.v);
  const float side = outside.dot(n) >= 0.0f ? 1.0f : -1.0f;
  const Eigen::Vector4f texel = m.normal_layer.Sample(hit.prim, hit.u, hit.v, FootprintMetres(hit, r.dir, r.angle, ng));
  const float tx = (2 * texel.x() - 1) * m.normal_scale, ty = (2 * texel.y() - 1) * m.normal_scale;
  const float tz = 2 * texel.z() - 1;
  const Eigen::Vector3f mapped = side * (tx * x.normalized() + ty * y.normalized()) + tz * n;
  const float len = mapped.norm();
  return len > 1e-12f ? Eigen::Vector3f(mapped / len) : n;
}

float Occlusion(const MeshShading& m, const SampleRecord& r, const Eigen::Vector3f& ng) {
  const Hit& hit = r.hit;
  const float open = m.occlusion_layer.Sample(hit.prim, hit.u, hit.v, FootprintMetres(hit, r.dir, r.angle, ng)).x();
  return 1.0f + m.occlusion_strength * (open - 1.0f);
}

Eigen::Vector3f Emission(const MeshShading& m, const SampleRecord& r) {
  if (m.emissive_layer.texture == nullptr) return m.emissive;
  const Hit& hit = r.hit;
  Eigen::Vector3f ng = m.triangles[hit.prim].face_normal;  // the footprint ignores its sign
  if (ng.squaredNorm() == 0.0f) ng = -r.dir;                // as SurfaceNormals
  const Eigen::Vector4f texel = m.emissive_layer.Sample(hit.prim, hit.u, hit.v, FootprintMetres(hit, r.dir, r.angle, ng));
  return m.emissive.cwiseProduct(texel.head<3>());
}

}  // namespace rigsim
