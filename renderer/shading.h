// Shading a camera ray's hit: the data each mesh's material and triangles give shading, prepared
// once per mesh so that shading a hit is table look-ups only; the sun and the sky; and the radiance
// a hit sends towards the camera.
//
// Lighting model: the material's albedo (base colour x vertex colour x texture) lit by the sky
// (brighter from above, a darker ground bounce from below, scaled by the occlusion map) and by the
// sun (Lambert on the side it lights, hard shadows from one shadow ray), plus the material's
// emission; KHR_materials_unlit shows the albedo itself. Surfaces are lit from the side they are
// seen from. The functions on the path of every hit are inline; the rare branches (normal map,
// occlusion map, emission) are out of line to keep that path short.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <map>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "renderer/renderer.h"
#include "renderer/texture_sampling.h"
#include "scene/scene.h"

namespace rigsim {

// The mip pyramids of a scene's textures as its materials read them. Built once; shading data
// points into them, so they are not moved or resized afterwards.
struct MaterialTextures {
  std::vector<MipTexture> colour;  // colour (sRGB codes), by Scene::textures index
  std::map<int, MipTexture> data;  // normal and occlusion maps (codes as they are), by Scene::textures index
};

// The scene's textures must have passed scene/scene_validation.h.
MaterialTextures BuildMaterialTextures(const Scene& scene);

// A per-corner attribute at barycentric (u, v) of a hit (Embree's: weight u on corner 1, v on 2).
template <typename T>
T AtHit(const std::array<T, 3>& corners, float u, float v) {
  return (1 - u - v) * corners[0] + u * corners[1] + v * corners[2];
}

// A texture a mesh samples through its own coordinates (emission, normal map): per triangle its
// corners' coordinates and its texel density.
struct TextureLayer {
  const MipTexture* texture = nullptr;  // nullptr: none, or the mesh has no such coordinates
  std::vector<std::array<Eigen::Vector2f, 3>> corners;
  std::vector<float> texels_per_metre;

  void Build(const MipTexture* tex, const SceneMesh& mesh, const std::vector<Eigen::Vector2f>& texcoords);

  // Linear RGBA at barycentric (u, v) of triangle `prim`, for a pixel footprint of `footprint_m`.
  Eigen::Vector4f Sample(unsigned prim, float u, float v, float footprint_m) const {
    const Eigen::Vector2f uv = AtHit(corners[prim], u, v);
    return SampleTexture(*texture, uv.x(), uv.y(), LodOf(footprint_m * texels_per_metre[prim]));
  }
};

// A triangle's tangent frame for normal mapping.
struct TangentFrame {
  Eigen::Vector3f along_u;   // dP/du, world
  Eigen::Vector3f up_image;  // -dP/dv: towards the texture's top row, where normal maps' +Y points
};

// What shading needs of one mesh: its labels, its material resolved, and per-triangle copies of
// its vertex attributes.
struct MeshShading {
  uint8_t class_id = 0;
  uint16_t instance_id = 0;
  Eigen::Vector4f base_color = Eigen::Vector4f(0.5f, 0.5f, 0.5f, 1.0f);  // linear RGBA factor
  const MipTexture* texture = nullptr;  // nullptr: no texture or no texcoords
  bool alpha_tested = false;
  float alpha_cutoff = 0.5f;
  bool unlit = false;  // KHR_materials_unlit: no sun, no sky, no shadow ray
  Eigen::Vector3f emissive = Eigen::Vector3f::Zero();  // linear RGB, added to the reflected light
  bool emits = false;  // some emission to add (never for unlit materials, which show their colour)
  TextureLayer emissive_layer;                          // multiplies `emissive`
  TextureLayer normal_layer;                            // the normal map
  float normal_scale = 1.0f;
  TextureLayer occlusion_layer;                         // scales the sky light
  float occlusion_strength = 1.0f;
  // How much of a mirror the surface is (GlossOf): 0, the surface reflects no world (and costs
  // no reflected ray); 1, a perfect mirror. Its material's metallic factor mixes the reflection's
  // colour (SpecularMix).
  float gloss = 0.0f;
  float metallic = 0.0f;
  // Per-triangle shading data, copied out of the indexed mesh so that shading a hit reads one or
  // two cache lines instead of chasing the index buffer into three vertex arrays (that chase cost
  // more than a third of the shading time in the street benchmark).
  struct TriangleShading {
    Eigen::Vector3f face_normal;  // unit (zero for degenerate triangles)
    float texels_per_metre = 0.0f;  // level-0 texels per metre on the surface, for mip selection
  };
  std::vector<TriangleShading> triangles;
  std::vector<std::array<Eigen::Vector2f, 3>> corner_texcoords;  // per triangle, when textured
  std::vector<std::array<Eigen::Vector3f, 3>> corner_normals;    // per triangle, only for smooth meshes
  std::vector<std::array<Eigen::Vector4f, 3>> corner_colors;     // per triangle, only with COLOR_0
  // Per triangle, only with a normal map: its tangent frame.
  std::vector<TangentFrame> tangent_frames;
};

// The shading data a hit's geom indexes: the scene's meshes below kAttachedGeom, and from it on
// those of a scene attached to the rig (Renderer::SetAttached), turned into the world frame.
constexpr unsigned kAttachedGeom = 1u << 30;

struct MeshTable {
  const std::vector<MeshShading>* scene = nullptr;
  const std::vector<MeshShading>* attached = nullptr;
  const MeshShading& operator[](unsigned geom) const {
    return geom < kAttachedGeom ? (*scene)[geom] : (*attached)[geom - kAttachedGeom];
  }
};

// `m` with its normals and tangent frames turned by `rotation` (a mesh moved rigidly).
MeshShading RotatedShading(const MeshShading& m, const Eigen::Matrix3f& rotation);

// The shading data of `mesh`, whose material and textures are those of `scene` (mip pyramids in
// `textures`, which must outlive the result). `mesh` must have passed scene/scene_validation.h.
MeshShading PrepareMeshShading(const SceneMesh& mesh, const Scene& scene, const MaterialTextures& textures);

// The material's base colour at a hit, before its texture: the factor times the interpolated
// vertex colour (COLOR_0) when the mesh has one.
inline Eigen::Vector4f BaseColorAt(const MeshShading& m, unsigned prim, float u, float v) {
  if (m.corner_colors.empty()) return m.base_color;
  return m.base_color.cwiseProduct(AtHit(m.corner_colors[prim], u, v));
}

inline Eigen::Vector2f InterpolateTexcoord(const MeshShading& m, unsigned prim, float u, float v) {
  return AtHit(m.corner_texcoords[prim], u, v);
}

// Alpha of the material at a hit, tested at full resolution so that the cut-out does not depend
// on distance.
inline float AlphaAt(const MeshShading& m, unsigned prim, float u, float v) {
  float alpha = BaseColorAt(m, prim, u, v)[3];
  if (m.texture != nullptr) {
    const Eigen::Vector2f uv = InterpolateTexcoord(m, prim, u, v);
    alpha *= SampleTexture(*m.texture, uv.x(), uv.y(), 0.0f)[3];
  }
  return alpha;
}

// One specular bounce. A material rougher than kGlossyRoughness is shaded as a diffuse surface
// only; a smoother one also reflects the world: one ray leaves its hit in the mirror direction,
// its hit is shaded as a camera ray's would be (sun, shadow and sky; a glossy surface it meets is
// shaded without a further bounce) or it sees the sky, and that radiance is mixed in:
//   L = (1 - g k) L_surface + g F L_reflected,    g = 1 - roughness / kGlossyRoughness,
//   F = F0 + (1 - F0) (1 - cos theta)^5 (Schlick), F0 = 0.04 (1 - metallic) + albedo metallic,
//   k = metallic + (1 - metallic) F_0.04: a metal keeps none of its diffuse light, a dielectric
//   what it does not reflect. theta is the angle between the ray and the shading normal.
// The threshold keeps every rough material's radiance (and so the shipped scenes' bytes) as it
// was; a smooth surface's reflection fades out continuously as its roughness nears it.
constexpr float kGlossyRoughness = 0.3f;
constexpr float kDielectricF0 = 0.04f;

// g above for a material (0 for unlit ones, which show their colour).
inline float GlossOf(const Material& material) {
  if (material.unlit || !(material.roughness < kGlossyRoughness)) return 0.0f;
  return 1.0f - material.roughness / kGlossyRoughness;
}

// The direction a ray `dir` leaves a surface in after a mirror reflection about the shading normal
// `n` (facing the ray); about the geometric normal `ng` when the shading normal would send it
// into the surface.
inline Eigen::Vector3f MirrorDirection(const Eigen::Vector3f& dir, const Eigen::Vector3f& n, const Eigen::Vector3f& ng) {
  Eigen::Vector3f out = dir - 2.0f * dir.dot(n) * n;
  if (!(out.dot(ng) > 0.0f)) out = dir - 2.0f * dir.dot(ng) * ng;
  return out.normalized();
}

// How a glossy hit's own radiance and its reflection combine (the law above).
struct SpecularMix {
  float keep = 1.0f;                                          // factor of L_surface
  Eigen::Vector3f reflect = Eigen::Vector3f::Zero();          // factor of L_reflected, per channel
};

inline SpecularMix SpecularMixOf(float gloss, float metallic, const Eigen::Vector3f& albedo, float cos_theta) {
  const float c = std::clamp(1.0f - cos_theta, 0.0f, 1.0f);
  const float c5 = (c * c) * (c * c) * c;
  const Eigen::Vector3f f0 = Eigen::Vector3f::Constant(kDielectricF0 * (1.0f - metallic)) + metallic * albedo;
  SpecularMix mix;
  mix.reflect = gloss * (f0 + c5 * (Eigen::Vector3f::Ones() - f0));
  const float dielectric = kDielectricF0 + c5 * (1.0f - kDielectricF0);
  mix.keep = 1.0f - gloss * (metallic + (1.0f - metallic) * dielectric);
  return mix;
}

// Everything shading needs for one Render call, in float.
struct ShadeParams {
  Eigen::Vector3f sun_dir;
  float sun_intensity;
  float sky_intensity;
  bool shadows;
};

ShadeParams ShadeParamsOf(const RenderOptions& options);

// Visible sky radiance is brighter than the ambient it casts on a surface, which sees only part
// of an unoccluded sky in practice.
constexpr float kSkyViewGain = 2.2f;
// Ambient on a downward-facing surface relative to an upward-facing one (ground bounce).
constexpr float kGroundBounce = 0.3f;

// What a ray that hits nothing sees in direction `dir`.
inline Eigen::Vector3f SkyRadiance(const Eigen::Vector3f& dir, const ShadeParams& p) {
  const Eigen::Vector3f horizon(0.75f, 0.82f, 0.90f), zenith(0.22f, 0.40f, 0.80f), ground(0.35f, 0.33f, 0.30f);
  const float up = dir.y();
  const Eigen::Vector3f c = up >= 0 ? Eigen::Vector3f(horizon + std::sqrt(up) * (zenith - horizon))
                                    : Eigen::Vector3f(horizon + std::min(1.0f, -4.0f * up) * (ground - horizon));
  return c * (p.sky_intensity * kSkyViewGain);
}

struct Hit {
  bool hit = false;
  unsigned geom = 0;  // the mesh's index (Embree geomID)
  unsigned prim = 0;  // the triangle's index in the mesh
  float u = 0, v = 0, t = 0;
};

// One camera ray that contributes to its pixel's colour, through the stages of shading a tile
// row: traced, shaded without the sun, then lit once its shadow ray is answered.
struct SampleRecord {
  Hit hit;
  Eigen::Vector3f dir;    // world direction of the camera ray
  float time = 0;         // the camera ray's Embree time, which its shadow ray shares
  float angle = 0;        // the ray's angular footprint (radians), for texture filtering
  int pixel = 0;          // in the tile
  Eigen::Vector3f albedo;
  float light = 0;        // without the sun
  float sun_light = 0;    // what the sun adds when the shadow ray is clear
  bool sun_ray = false;   // the sun lights this side: a shadow ray is due
  // The hit point (world) when collected (CollectRecords), then the shadow ray's origin.
  Eigen::Vector3f shadow_origin;
  // ShareShadingWithinPixels: -1 when this record is lit by its own shading, else the index (in
  // the batch's records) of the earlier sample on the same triangle whose light it shares.
  int lit_by = -1;
};

// At spp > 1: the samples of one pixel that hit the same triangle share one lighting, computed
// for the first of them (normals, sky and sun, one shadow ray); each keeps its own albedo (texture
// look-up at its own point and footprint, AlbedoOnly), so textures are as sharp as with shading per
// sample. Geometric edges and alpha cut-outs stay anti-aliased by the samples; a shadow edge that
// crosses a triangle inside a pixel is not. Lighting and shadow rays per sample would be most of
// the extra time of a sample. `records` are in pixel order (CollectRecords); up to 8 triangles per
// pixel share (samples beyond are lit alone).
inline void ShareShadingWithinPixels(std::vector<SampleRecord>& records) {
  constexpr int kMaxShared = 8;
  for (size_t i = 0; i < records.size();) {
    const int pixel = records[i].pixel;
    int leaders[kMaxShared];
    int num_leaders = 0;
    for (; i < records.size() && records[i].pixel == pixel; ++i) {
      SampleRecord& r = records[i];
      if (!r.hit.hit) continue;
      int l = 0;
      while (l < num_leaders && (records[leaders[l]].hit.geom != r.hit.geom || records[leaders[l]].hit.prim != r.hit.prim)) ++l;
      if (l < num_leaders) {
        r.lit_by = leaders[l];
      } else if (num_leaders < kMaxShared) {
        leaders[num_leaders++] = int(i);
      }
    }
  }
}

// Pixel footprint on the surface (major axis), for the textures' mip levels: `angle` is the
// ray's angular footprint, `ng` the geometric normal.
[[gnu::always_inline]] inline float FootprintMetres(const Hit& hit, const Eigen::Vector3f& dir, float angle,
                                                    const Eigen::Vector3f& ng) {
  return hit.t * angle / std::max(std::abs(ng.dot(dir)), 0.1f);
}

// Geometric (ng) and shading (n) normals at a hit on mesh `m`, both facing the incoming ray:
// surfaces are lit from the side they are seen from.
inline void SurfaceNormals(const MeshShading& m, const Hit& hit, const Eigen::Vector3f& dir, Eigen::Vector3f* ng_out,
                           Eigen::Vector3f* n_out) {
  Eigen::Vector3f ng = m.triangles[hit.prim].face_normal;
  if (ng.squaredNorm() == 0.0f) ng = -dir;
  if (ng.dot(dir) > 0) ng = -ng;
  Eigen::Vector3f n = ng;
  if (!m.corner_normals.empty()) {
    const Eigen::Vector3f ni = AtHit(m.corner_normals[hit.prim], hit.u, hit.v);
    const float len = ni.norm();
    if (len > 1e-12f) {
      n = ni / len;
      if (n.dot(dir) > 0) n = -n;
    }
  }
  *ng_out = ng;
  *n_out = n;
}

// The sun contributes (and, with shadows on, a shadow ray is cast) only on the lit side.
inline bool NeedsSunRay(const Eigen::Vector3f& ng, const Eigen::Vector3f& n, const ShadeParams& p) {
  return n.dot(p.sun_dir) > 0 && ng.dot(p.sun_dir) > 0;
}

// Start of the shadow ray: the hit `point` offset along the geometric normal, scaled with float
// precision at this distance.
inline Eigen::Vector3f ShadowRayOriginAt(const Hit& hit, const Eigen::Vector3f& point, const Eigen::Vector3f& ng) {
  const float eps = 1e-4f * (1.0f + std::max(point.cwiseAbs().maxCoeff(), hit.t));
  return point + eps * ng;
}

inline Eigen::Vector3f ShadowRayOrigin(const Hit& hit, const Eigen::Vector3f& origin, const Eigen::Vector3f& dir,
                                       const Eigen::Vector3f& ng) {
  return ShadowRayOriginAt(hit, origin + hit.t * dir, ng);
}

// The shading normal `n` (facing the ray) turned by the mesh's normal map. The map's axes are
// the triangle's tangent frame made orthogonal to n; its +Z is the surface's outside, so seen
// from the back the whole frame turns over.
[[gnu::noinline]] Eigen::Vector3f NormalMapped(const MeshShading& m, const SampleRecord& r, const Eigen::Vector3f& ng,
                                               const Eigen::Vector3f& n);

// How much of the sky the material's occlusion map lets through at the hit.
[[gnu::noinline]] float Occlusion(const MeshShading& m, const SampleRecord& r, const Eigen::Vector3f& ng);

// What an emissive surface gives off towards the camera ray.
[[gnu::noinline]] Eigen::Vector3f Emission(const MeshShading& m, const SampleRecord& r);

// Everything about a camera ray's hit on mesh `m` except the sun's shadow ray. Shading a batch of hits before tracing their shadow rays lets the CPU overlap the
// hits' independent chains of loads and arithmetic instead of running each between two Embree
// traversals.
[[gnu::always_inline]] inline void ShadeWithoutShadow(const MeshShading& m, SampleRecord& r, const ShadeParams& p) {
  const Hit& hit = r.hit;
  Eigen::Vector3f ng, n;
  SurfaceNormals(m, hit, r.dir, &ng, &n);
  if (m.normal_layer.texture != nullptr) n = NormalMapped(m, r, ng, n);

  Eigen::Vector4f base = BaseColorAt(m, hit.prim, hit.u, hit.v);
  if (m.texture != nullptr) {
    const Eigen::Vector2f uv = InterpolateTexcoord(m, hit.prim, hit.u, hit.v);
    const float texels = FootprintMetres(hit, r.dir, r.angle, ng) * m.triangles[hit.prim].texels_per_metre;
    base = base.cwiseProduct(SampleTexture(*m.texture, uv.x(), uv.y(), LodOf(texels)));
  }
  r.albedo = base.head<3>();
  if (m.unlit) {  // as the Khronos viewer shows it: the colour itself, at exposure 1 white is white
    r.light = 1.0f;
    r.sun_ray = false;
    return;
  }

  const float up = std::clamp(n.y(), -1.0f, 1.0f);
  r.light = p.sky_intensity * (0.5f * (1 + up) + kGroundBounce * 0.5f * (1 - up));
  if (m.occlusion_layer.texture != nullptr) r.light *= Occlusion(m, r, ng);
  r.sun_ray = NeedsSunRay(ng, n, p);
  if (r.sun_ray) {
    r.sun_light = p.sun_intensity * n.dot(p.sun_dir);
    r.shadow_origin = ShadowRayOriginAt(hit, r.shadow_origin, ng);
  }
}

// The albedo alone of a sample lit by another's shading (ShareShadingWithinPixels).
[[gnu::always_inline]] inline void AlbedoOnly(const MeshShading& m, SampleRecord& r) {
  const Hit& hit = r.hit;
  Eigen::Vector4f base = BaseColorAt(m, hit.prim, hit.u, hit.v);
  if (m.texture != nullptr) {
    Eigen::Vector3f ng = m.triangles[hit.prim].face_normal;  // the footprint ignores its sign
    if (ng.squaredNorm() == 0.0f) ng = -r.dir;              // as SurfaceNormals
    const Eigen::Vector2f uv = InterpolateTexcoord(m, hit.prim, hit.u, hit.v);
    const float texels = FootprintMetres(hit, r.dir, r.angle, ng) * m.triangles[hit.prim].texels_per_metre;
    base = base.cwiseProduct(SampleTexture(*m.texture, uv.x(), uv.y(), LodOf(texels)));
  }
  r.albedo = base.head<3>();
}

// Radiance leaving the hit on mesh `m` towards the camera, once its shadow ray (if any) is answered.
[[gnu::always_inline]] inline Eigen::Vector3f FinishShading(const MeshShading& m, SampleRecord& r, bool sun_visible) {
  if (r.sun_ray && sun_visible) r.light += r.sun_light;
  const Eigen::Vector3f reflected = r.albedo * r.light;
  return m.emits ? Eigen::Vector3f(reflected + Emission(m, r)) : reflected;
}

// Radiance of a sample lit as `lit` (ShareShadingWithinPixels), whose FinishShading has run.
[[gnu::always_inline]] inline Eigen::Vector3f LitAs(const MeshShading& m, SampleRecord& r, const SampleRecord& lit) {
  const Eigen::Vector3f reflected = r.albedo * lit.light;
  return m.emits ? Eigen::Vector3f(reflected + Emission(m, r)) : reflected;
}

}  // namespace rigsim
