#include "renderer/renderer.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <bit>
#include <chrono>
#include <cmath>
#include <limits>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <embree3/rtcore.h>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "labels/cityscapes.h"
#include "renderer/srgb.h"

namespace rigsim {
namespace {

constexpr int kTileSize = 32;
// A tile row is shaded in batches of pixels of at most this many samples together (at least one
// pixel): a whole row up to 32 spp, and a bounded buffer at any spp.
constexpr int kMaxBatchSamples = 1024;

int PixelsPerBatch(int spp) { return std::clamp(kMaxBatchSamples / spp, 1, kTileSize); }


// ---------------------------------------------------------------------------------------------
// Counter-based random numbers: a pure function of (seed, pixel, sample), so the image does not
// depend on which thread renders which tile.

uint64_t Mix64(uint64_t z) {
  z += 0x9e3779b97f4a7c15ull;
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
  return z ^ (z >> 31);
}

uint64_t HashSample(uint64_t seed, int x, int y, int sample, int stream) {
  uint64_t h = Mix64(seed);
  h = Mix64(h ^ (uint64_t(uint32_t(x)) << 32 | uint32_t(y)));
  h = Mix64(h ^ (uint64_t(uint32_t(sample)) << 8 | uint32_t(stream)));
  return h;
}

float UnitFloat(uint64_t h) { return float(h >> 40) * 0x1p-24f; }  // [0, 1)

// ---------------------------------------------------------------------------------------------
// Textures: a box-filtered mip pyramid per texture, stored in linear light with 16 bits per
// channel, at twice the memory of 8-bit sRGB levels. Filtering reads texels as they are instead
// of through a table look-up per channel (a one-thread street frame: 250 -> 237 ms), and the
// levels are not re-quantised to 8-bit sRGB at every halving.

constexpr float kTexelUnit = 65535.0f;  // stored value of a linear 1.0

// One level, stored with a border one texel wide that holds the texels the sampler's wrap modes
// put beside the edges. With coordinates reduced to [0, 1] (ReduceCoordinate), a bilinear
// look-up's four texels are then always in memory next to each other: no wrapping per texel, and
// each pair of neighbours is one load.
struct MipLevel {
  int width = 0;   // without the border
  int height = 0;
  int stride = 0;  // texels per stored row: width + 2
  float fixed_width = 0, fixed_height = 0;  // width and height * 65536 (16.16 fixed point)
  // (height + 2) rows of RGBA, linear * kTexelUnit, and one texel more: a two-texel load at the
  // last texel (nearest filtering at s = t = 1) stays inside.
  std::vector<uint16_t> rgba;

  MipLevel() = default;
  MipLevel(int w, int h)
      : width(w), height(h), stride(w + 2), fixed_width(float(w) * 65536.0f), fixed_height(float(h) * 65536.0f),
        rgba((size_t(w + 2) * (h + 2) + 1) * 4) {}
  // x in [-1, width], y in [-1, height].
  const uint16_t* Texel(int x, int y) const { return &rgba[(size_t(y + 1) * stride + (x + 1)) * 4]; }
  uint16_t* Texel(int x, int y) { return &rgba[(size_t(y + 1) * stride + (x + 1)) * 4]; }
};

struct MipTexture {
  std::vector<MipLevel> levels;
  WrapMode wrap_s = WrapMode::kRepeat;
  WrapMode wrap_t = WrapMode::kRepeat;
  bool nearest = false;      // magnification
  bool min_nearest = false;  // minification, within a level
  MipFilter mip = MipFilter::kLinear;
  float texel_scale = 1.0f;  // sqrt(width * height) of level 0: texels per uv unit
};

// The texel that index i (-1 <= i <= n) shows under a wrap mode.
int WrapIndex(int i, int n, WrapMode mode) {
  if (i >= 0 && i < n) return i;
  switch (mode) {
    case WrapMode::kClampToEdge:
      return std::clamp(i, 0, n - 1);
    case WrapMode::kMirroredRepeat:  // ... t1 t0 | t0 t1 ... t(n-1) | t(n-1) ...
      return i < 0 ? std::min(-i - 1, n - 1) : std::max(2 * n - 1 - i, 0);
    case WrapMode::kRepeat:
    default:
      return i < 0 ? n - 1 : 0;
  }
}

// Fills the border from the level's own texels.
void FillBorder(MipLevel& level, WrapMode wrap_s, WrapMode wrap_t) {
  auto fill = [&](int x, int y) {
    std::copy_n(level.Texel(WrapIndex(x, level.width, wrap_s), WrapIndex(y, level.height, wrap_t)), 4,
                level.Texel(x, y));
  };
  for (int y = 0; y < level.height; ++y) {
    fill(-1, y);
    fill(level.width, y);
  }
  for (int x = -1; x <= level.width; ++x) {  // corners included
    fill(x, -1);
    fill(x, level.height);
  }
}

// What a texture's RGB codes hold: colour (base colour, emission) in sRGB encoding, or data
// (normal maps) as they are.
enum class TexelEncoding { kSrgb, kLinear };

// Level 0: the source's RGB decoded to linear values; alpha is linear already.
MipLevel LinearLevel(const Texture& texture, TexelEncoding encoding) {
  std::array<uint16_t, 256> colour{};
  for (int code = 0; code < 256; ++code) {
    colour[code] = encoding == TexelEncoding::kSrgb ? uint16_t(std::lround(LinearFromSrgbCode(uint8_t(code)) * kTexelUnit))
                                                    : uint16_t(code * 257);
  }
  MipLevel level(texture.width, texture.height);
  for (int y = 0; y < texture.height; ++y) {
    for (int x = 0; x < texture.width; ++x) {
      const uint8_t* in = &texture.rgba[(size_t(y) * texture.width + x) * 4];
      uint16_t* out = level.Texel(x, y);
      for (int c = 0; c < 3; ++c) out[c] = colour[in[c]];
      out[3] = uint16_t(in[3] * 257);  // 255 -> 65535
    }
  }
  return level;
}

// Averages 2x2 blocks (in linear light, so distant textures do not darken).
MipLevel Downsample(const MipLevel& src) {
  MipLevel dst(std::max(1, src.width / 2), std::max(1, src.height / 2));
  for (int y = 0; y < dst.height; ++y) {
    const int y0 = std::min(2 * y, src.height - 1), y1 = std::min(2 * y + 1, src.height - 1);
    for (int x = 0; x < dst.width; ++x) {
      const int x0 = std::min(2 * x, src.width - 1), x1 = std::min(2 * x + 1, src.width - 1);
      const uint16_t* p[4] = {src.Texel(x0, y0), src.Texel(x1, y0), src.Texel(x0, y1), src.Texel(x1, y1)};
      uint16_t* out = dst.Texel(x, y);
      for (int c = 0; c < 4; ++c) out[c] = uint16_t((uint32_t(p[0][c]) + p[1][c] + p[2][c] + p[3][c] + 2) / 4);
    }
  }
  return dst;
}

MipTexture BuildMipTexture(const Texture& texture, TexelEncoding encoding, const std::string& where) {
  if (texture.width <= 0 || texture.height <= 0 ||
      texture.rgba.size() != size_t(texture.width) * texture.height * 4) {
    throw std::invalid_argument(where + ": texture '" + texture.name + "' has size " + std::to_string(texture.width) +
                                "x" + std::to_string(texture.height) + " but " +
                                std::to_string(texture.rgba.size()) + " bytes (RGBA8 expected)");
  }
  MipTexture mip;
  mip.wrap_s = texture.wrap_s;
  mip.wrap_t = texture.wrap_t;
  mip.nearest = texture.nearest;
  mip.min_nearest = texture.min_nearest;
  mip.mip = texture.mip;
  mip.texel_scale = std::sqrt(float(texture.width) * float(texture.height));
  mip.levels.push_back(LinearLevel(texture, encoding));
  while (mip.levels.back().width > 1 || mip.levels.back().height > 1) {
    mip.levels.push_back(Downsample(mip.levels.back()));
  }
  for (MipLevel& level : mip.levels) FillBorder(level, texture.wrap_s, texture.wrap_t);
  return mip;
}

// floor(x) without a call or SSE4.1's roundss: floats of magnitude 2^23 and beyond are whole
// numbers already.
[[gnu::always_inline]] inline float FloorFloat(float x) {
  if (!(std::abs(x) < 8388608.0f)) return x;
  const float truncated = float(int(x));
  return truncated > x ? truncated - 1.0f : truncated;
}

// Brings a texture coordinate into [0, 1] under its wrap mode. A mirrored coordinate folds onto
// [0, 1] exactly: the mirrored texture, and any symmetric filter of it, is the same at s and 2 - s.
[[gnu::always_inline]] inline float ReduceCoordinate(float s, WrapMode mode) {
  switch (mode) {
    case WrapMode::kRepeat:
      return s - FloorFloat(s);  // [0, 1]: 1 when s is a tiny negative number
    case WrapMode::kMirroredRepeat: {
      const float r = s - 2.0f * FloorFloat(0.5f * s);  // [0, 2]
      return r > 1.0f ? 2.0f - r : r;
    }
    case WrapMode::kClampToEdge:
    default:
      return std::clamp(s, 0.0f, 1.0f);
  }
}

// Texel arithmetic in 16-bit integers, on two texels at once (one SSE2 register): a bilinear
// look-up is two loads and three blends, and the result becomes float once, at the end, instead
// of once per texel. The portable branch does the same integer arithmetic, so both give the same
// bytes.
#if defined(__SSE2__)
using TexelPair = __m128i;  // lanes 0-3: texel a (RGBA), lanes 4-7: texel b
#else
struct TexelPair {
  std::array<uint16_t, 8> lane;
};
#endif

// Texels p and p + 1 (a stored row's neighbours).
[[gnu::always_inline]] inline TexelPair LoadTexelPair(const uint16_t* p) {
#if defined(__SSE2__)
  return _mm_loadu_si128(reinterpret_cast<const __m128i*>(p));
#else
  return TexelPair{{p[0], p[1], p[2], p[3], p[4], p[5], p[6], p[7]}};
#endif
}

// The first texel of each pair, joined as (a of `first`, a of `second`).
[[gnu::always_inline]] inline TexelPair JoinFirsts(TexelPair first, TexelPair second) {
#if defined(__SSE2__)
  return _mm_unpacklo_epi64(first, second);
#else
  return TexelPair{{first.lane[0], first.lane[1], first.lane[2], first.lane[3], second.lane[0], second.lane[1],
                    second.lane[2], second.lane[3]}};
#endif
}

// a + (b - a) * w / 65536 into the first texel, as a - hi(a * w) + hi(b * w) with hi(p) = p >> 16:
// within one unit, exact when w = 0 or a = b (an opaque texel stays exactly opaque), and never
// beyond 65535.
[[gnu::always_inline]] inline TexelPair LerpPair(TexelPair pair, uint16_t w) {
#if defined(__SSE2__)
  const __m128i scaled = _mm_mulhi_epu16(pair, _mm_set1_epi16(int16_t(w)));
  return _mm_add_epi16(pair, _mm_sub_epi16(_mm_srli_si128(scaled, 8), scaled));
#else
  TexelPair out = pair;
  for (int c = 0; c < 4; ++c) {
    const uint32_t a = pair.lane[c], b = pair.lane[c + 4];
    out.lane[c] = uint16_t(a - ((a * w) >> 16) + ((b * w) >> 16));
  }
  return out;
#endif
}

// The first texel in linear units.
[[gnu::always_inline]] inline Eigen::Vector4f FirstTexelLinear(TexelPair pair) {
#if defined(__SSE2__)
  Eigen::Vector4f out;
  const __m128 stored = _mm_cvtepi32_ps(_mm_unpacklo_epi16(pair, _mm_setzero_si128()));
  _mm_storeu_ps(out.data(), _mm_mul_ps(stored, _mm_set1_ps(1.0f / kTexelUnit)));
  return out;
#else
  return Eigen::Vector4f(pair.lane[0], pair.lane[1], pair.lane[2], pair.lane[3]) * (1.0f / kTexelUnit);
#endif
}

// A blend weight in [0, 1] as a 16-bit fraction.
[[gnu::always_inline]] inline uint16_t WeightU16(float f) { return uint16_t(std::clamp(int(f * 65536.0f), 0, 65535)); }

// `s`, `t` in [0, 1] (ReduceCoordinate); texel centres are at (i + 0.5) / width (glTF: uv
// (0, 0) is the image's top-left corner). The texel grid position is taken in 16.16 fixed point:
// the integer part picks the texels and the fraction is the blend weight, with no std::floor
// (a dozen instructions without SSE4.1). The four texels are at x0, x0 + 1 in [-1, width] and
// y0, y0 + 1 in [-1, height]: inside the bordered level.
[[gnu::always_inline]] inline TexelPair SampleBilinear(const MipLevel& level, float s, float t) {
  const int64_t fx = int64_t(s * level.fixed_width) - 32768;
  const int64_t fy = int64_t(t * level.fixed_height) - 32768;
  const uint16_t* top = level.Texel(int(fx >> 16), int(fy >> 16));  // arithmetic shift: floor
  const uint16_t wx = uint16_t(fx & 0xffff), wy = uint16_t(fy & 0xffff);
  return LerpPair(JoinFirsts(LerpPair(LoadTexelPair(top), wx), LerpPair(LoadTexelPair(top + 4 * level.stride), wx)),
                  wy);
}

// x = floor(s * width) is in [0, width]: width (s = 1) is the border texel, which is what s = 1
// shows under every wrap mode. (The pair's second texel is loaded and not used.)
TexelPair SampleNearest(const MipLevel& level, float s, float t) {
  return LoadTexelPair(level.Texel(int(s * float(level.width)), int(t * float(level.height))));
}

// log2 to within 0.09 (exponent plus the mantissa's linear part): plenty to pick mip levels and
// their blend, at a fraction of std::log2's cost per textured hit.
[[gnu::always_inline]] inline float FastLog2(float x) {
  const uint32_t bits = std::bit_cast<uint32_t>(x);
  const float mantissa = std::bit_cast<float>((bits & 0x007fffffu) | 0x3f800000u);  // in [1, 2)
  return float(int(bits >> 23) - 127) + (mantissa - 1.0f);
}

// Minification by a sampler other than LINEAR_MIPMAP_LINEAR (out of line: rare, and it keeps the
// common path short).
[[gnu::noinline]] TexelPair SampleMinifiedAsAsked(const MipTexture& tex, float s, float t, float lod) {
  auto sample_level = [&](int level) {
    return tex.min_nearest ? SampleNearest(tex.levels[level], s, t) : SampleBilinear(tex.levels[level], s, t);
  };
  const int last = int(tex.levels.size()) - 1;
  switch (tex.mip) {
    case MipFilter::kNone:
      return sample_level(0);
    case MipFilter::kNearest:
      return sample_level(std::min(last, int(lod + 0.5f)));
    case MipFilter::kLinear:
    default: {
      const int l0 = int(lod);
      if (l0 >= last) return sample_level(last);
      return LerpPair(JoinFirsts(sample_level(l0), sample_level(l0 + 1)), WeightU16(lod - float(l0)));
    }
  }
}

// Filtering as the texture's glTF sampler asks (trilinear unless it says otherwise); `lod` = log2
// of the footprint in level-0 texels, magnified when <= 0.
[[gnu::always_inline]] inline TexelPair SampleTexels(const MipTexture& tex, float s, float t, float lod) {
  if (!(lod > 0.0f)) return tex.nearest ? SampleNearest(tex.levels[0], s, t) : SampleBilinear(tex.levels[0], s, t);
  if (tex.mip != MipFilter::kLinear || tex.min_nearest) return SampleMinifiedAsAsked(tex, s, t, lod);
  const int last = int(tex.levels.size()) - 1;  // trilinear
  const int l0 = int(lod);
  if (l0 >= last) return SampleBilinear(tex.levels[last], s, t);
  return LerpPair(JoinFirsts(SampleBilinear(tex.levels[l0], s, t), SampleBilinear(tex.levels[l0 + 1], s, t)),
                  WeightU16(lod - float(l0)));
}

// Linear RGBA of the texture at (s, t).
[[gnu::always_inline]] inline Eigen::Vector4f SampleTexture(const MipTexture& tex, float s, float t, float lod) {
  if (!std::isfinite(s) || !std::isfinite(t)) return Eigen::Vector4f::Ones();
  return FirstTexelLinear(SampleTexels(tex, ReduceCoordinate(s, tex.wrap_s), ReduceCoordinate(t, tex.wrap_t), lod));
}

// ---------------------------------------------------------------------------------------------
// Scene data prepared once so that shading a hit is table look-ups only.

// A per-corner attribute at barycentric (u, v) of a hit (Embree's: weight u on corner 1, v on 2).
template <typename T>
T AtHit(const std::array<T, 3>& corners, float u, float v) {
  return (1 - u - v) * corners[0] + u * corners[1] + v * corners[2];
}

// Level-0 texels per metre of a triangle whose corners p0..p2 map to t0..t2, for a texture with
// `texel_scale` texels per uv unit: sqrt(uv area / world area) * texel_scale (0 when degenerate).
float TexelsPerMetre(const Eigen::Vector3f& p0, const Eigen::Vector3f& p1, const Eigen::Vector3f& p2,
                     const Eigen::Vector2f& t0, const Eigen::Vector2f& t1, const Eigen::Vector2f& t2,
                     float texel_scale) {
  const float area2 = (p1 - p0).cross(p2 - p0).norm();
  if (!(area2 > 0)) return 0.0f;
  const Eigen::Vector2f e1 = t1 - t0, e2 = t2 - t0;
  return std::sqrt(std::abs(e1.x() * e2.y() - e1.y() * e2.x()) / area2) * texel_scale;
}

// The mip level to read for a footprint of `texels` level-0 texels (magnified when <= 0).
[[gnu::always_inline]] inline float LodOf(float texels) { return texels > 0 ? FastLog2(texels) : 0.0f; }

// A texture a mesh samples through its own coordinates (emission, normal map): per triangle its
// corners' coordinates and its texel density.
struct TextureLayer {
  const MipTexture* texture = nullptr;  // nullptr: none, or the mesh has no such coordinates
  std::vector<std::array<Eigen::Vector2f, 3>> corners;
  std::vector<float> texels_per_metre;

  void Build(const MipTexture* tex, const SceneMesh& mesh, const std::vector<Eigen::Vector2f>& texcoords) {
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

struct MeshData {
  const SceneMesh* mesh = nullptr;
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



// The material's base colour at a hit, before its texture: the factor times the interpolated
// vertex colour (COLOR_0) when the mesh has one.
Eigen::Vector4f BaseColorAt(const MeshData& m, unsigned prim, float u, float v) {
  if (m.corner_colors.empty()) return m.base_color;
  return m.base_color.cwiseProduct(AtHit(m.corner_colors[prim], u, v));
}

Eigen::Vector2f InterpolateTexcoord(const MeshData& m, unsigned prim, float u, float v) {
  return AtHit(m.corner_texcoords[prim], u, v);
}

// Alpha of the material at a hit, tested at full resolution so that the cut-out does not depend
// on distance.
float AlphaAt(const MeshData& m, unsigned prim, float u, float v) {
  float alpha = BaseColorAt(m, prim, u, v)[3];
  if (m.texture != nullptr) {
    const Eigen::Vector2f uv = InterpolateTexcoord(m, prim, u, v);
    alpha *= SampleTexture(*m.texture, uv.x(), uv.y(), 0.0f)[3];
  }
  return alpha;
}

// Embree filter for MASK materials: rejecting a hit makes Embree continue the traversal beyond
// it, so the cut-out holds for camera rays and shadow rays alike.
void AlphaMaskFilter(const RTCFilterFunctionNArguments* args) {
  const MeshData& m = *static_cast<const MeshData*>(args->geometryUserPtr);
  for (unsigned i = 0; i < args->N; ++i) {
    if (args->valid[i] != -1) continue;
    const unsigned prim = RTCHitN_primID(args->hit, args->N, i);
    const float u = RTCHitN_u(args->hit, args->N, i);
    const float v = RTCHitN_v(args->hit, args->N, i);
    if (AlphaAt(m, prim, u, v) < m.alpha_cutoff) args->valid[i] = 0;
  }
}

// Collects Embree errors; Embree calls back from C code, so we record and throw later.
class EmbreeErrors {
 public:
  static void Callback(void* user, RTCError code, const char* message) {
    static_cast<EmbreeErrors*>(user)->Record(code, message);
  }
  void Record(RTCError code, const char* message) {
    std::lock_guard<std::mutex> lock(mutex_);
    if (first_.empty()) first_ = "Embree error " + std::to_string(int(code)) + ": " + (message ? message : "");
  }
  void ThrowIfAny(const std::string& during) {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!first_.empty()) throw std::runtime_error(during + ": " + first_);
  }

 private:
  std::mutex mutex_;
  std::string first_;
};

// Everything shading needs for one Render call, in float.
struct ShadeParams {
  Eigen::Vector3f sun_dir;
  float sun_intensity;
  float sky_intensity;
  bool shadows;
};

// Visible sky radiance is brighter than the ambient it casts on a surface, which sees only part
// of an unoccluded sky in practice.
constexpr float kSkyViewGain = 2.2f;
// Ambient on a downward-facing surface relative to an upward-facing one (ground bounce).
constexpr float kGroundBounce = 0.3f;

Eigen::Vector3f SkyRadiance(const Eigen::Vector3f& dir, const ShadeParams& p) {
  const Eigen::Vector3f horizon(0.75f, 0.82f, 0.90f), zenith(0.22f, 0.40f, 0.80f), ground(0.35f, 0.33f, 0.30f);
  const float up = dir.y();
  const Eigen::Vector3f c = up >= 0 ? Eigen::Vector3f(horizon + std::sqrt(up) * (zenith - horizon))
                                    : Eigen::Vector3f(horizon + std::min(1.0f, -4.0f * up) * (ground - horizon));
  return c * (p.sky_intensity * kSkyViewGain);
}

struct Hit {
  bool hit = false;
  unsigned geom = 0;
  unsigned prim = 0;
  float u = 0, v = 0, t = 0;
};

// One camera ray that contributes to its pixel's colour, through the stages of shading a tile
// row: traced, shaded without the sun, then lit once its shadow ray is answered.
struct SampleRecord {
  Hit hit;
  Eigen::Vector3f dir;    // world direction of the camera ray
  float angle = 0;        // the ray's angular footprint (radians), for texture filtering
  int pixel = 0;          // in the tile
  Eigen::Vector3f albedo;
  float light = 0;        // without the sun
  float sun_light = 0;    // what the sun adds when the shadow ray is clear
  bool sun_ray = false;   // the sun lights this side: a shadow ray is due
  Eigen::Vector3f shadow_origin;
};

// One tile's outputs, written pixel by pixel in cache and copied to the images row by row at the
// end. Written in place, every tile row started new cache lines in four images, a whole image
// row apart, one miss at a time (a one-thread street frame: 222 -> 209 ms).
struct TileOutputs {
  static constexpr int kPixels = kTileSize * kTileSize;
  std::array<uint8_t, 3 * kPixels> rgb;
  std::array<uint8_t, kPixels> label;
  std::array<uint16_t, kPixels> instance;
  std::array<float, kPixels> range;

  // A pixel outside the lens: black, label 0, instance 0, range 0.
  void SetInvalid(int pixel) {
    std::fill_n(&rgb[3 * pixel], 3, 0);
    label[pixel] = 0;
    instance[pixel] = 0;
    range[pixel] = 0.0f;
  }

  void CopyTo(RenderedView& view, int x_begin, int y_begin, int tile_width, int tile_height) const {
    if (tile_width == kTileSize) {  // constant sizes: inlined copies, not memmove calls
      CopyRows(view, x_begin, y_begin, kTileSize, tile_height);
    } else {
      CopyRows(view, x_begin, y_begin, tile_width, tile_height);
    }
  }

  [[gnu::always_inline]] void CopyRows(RenderedView& view, int x_begin, int y_begin, int tile_width,
                                       int tile_height) const {
    for (int row = 0; row < tile_height; ++row) {
      const int y = y_begin + row;
      const int first = row * kTileSize;
      std::copy_n(&rgb[3 * first], 3 * tile_width, &view.rgb.at(x_begin, y, 0));
      std::copy_n(&label[first], tile_width, &view.label.at(x_begin, y));
      std::copy_n(&instance[first], tile_width, &view.instance.at(x_begin, y));
      std::copy_n(&range[first], tile_width, &view.range.at(x_begin, y));
    }
  }
};

// Unit bearings of all pixel centres (invalid outside the lens) with each pixel's angular size
// (for texture filtering), computed once per camera: they depend on the intrinsics only, so a
// dataset's frames reuse them (Renderer::Impl caches them).
struct PixelCentreRays {
  int width = 0;
  std::vector<Eigen::Vector3f> bearings;  // float: half the memory traffic of the per-pixel read
  std::vector<float> angle;     // max angle to a valid neighbour's bearing (radians)
  std::vector<uint8_t> valid;
};

PixelCentreRays ComputePixelCentreRays(const Camera& camera) {
  const int width = camera.width(), height = camera.height();
  PixelCentreRays rays;
  rays.width = width;
  rays.bearings.assign(size_t(width) * height, Eigen::Vector3f::Zero());
  rays.valid.assign(rays.bearings.size(), 0);
  rays.angle.assign(rays.bearings.size(), 0.0f);
  tbb::parallel_for(0, height, [&](int y) {
    for (int x = 0; x < width; ++x) {
      if (const auto b = camera.CamFromImg(Eigen::Vector2d(x, y))) {
        rays.bearings[size_t(y) * width + x] = b->normalized().cast<float>();
        rays.valid[size_t(y) * width + x] = 1;
      }
    }
  });
  const float fallback = float(1.0 / std::max(camera.fx(), camera.fy()));
  tbb::parallel_for(0, height, [&](int y) {
    for (int x = 0; x < width; ++x) {
      const size_t idx = size_t(y) * width + x;
      if (!rays.valid[idx]) continue;
      float a = 0.0f;
      auto neighbour = [&](int nx, int ny) {
        if (nx < 0 || ny < 0 || nx >= width || ny >= height) return;
        const size_t n = size_t(ny) * width + nx;
        if (rays.valid[n]) a = std::max(a, float((rays.bearings[n] - rays.bearings[idx]).norm()));
      };
      neighbour(x + 1, y);
      neighbour(x - 1, y);
      neighbour(x, y + 1);
      neighbour(x, y - 1);
      rays.angle[idx] = a > 0.0f ? a : fallback;
    }
  });
  return rays;
}

}  // namespace

// ---------------------------------------------------------------------------------------------

struct Renderer::Impl {
  mutable EmbreeErrors errors;  // written from Embree callbacks during const renders
  const Scene* scene_ptr = nullptr;  // materials and textures; meshes may come from SetMeshes
  std::string source;                // for messages
  // Pixel-centre rays of the cameras rendered so far, keyed by model, size and parameters.
  mutable std::mutex centre_rays_mutex;
  mutable std::map<std::vector<double>, std::shared_ptr<const PixelCentreRays>> centre_rays;
  static constexpr size_t kMaxCachedCameras = 8;  // ~27 MB each at 1280x720
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  std::vector<MipTexture> textures;               // colour, by Scene::textures index
  std::map<int, MipTexture> data_textures;        // normal and occlusion maps, by Scene::textures index
  std::vector<MeshData> meshes;  // index == Embree geomID

  // (Re)builds the per-mesh data and the Embree scene from `meshes` (materials and textures of
  // *scene_ptr). Throws std::invalid_argument naming the mesh when it is inconsistent.
  void BuildGeometry(const std::vector<SceneMesh>& meshes);

  ~Impl() {
    if (scene) rtcReleaseScene(scene);
    if (device) rtcReleaseDevice(device);
  }

  // The camera's pixel-centre rays, computed on first use (outside the lock: another thread may
  // compute the same rays meanwhile; both results are identical).
  std::shared_ptr<const PixelCentreRays> CentreRays(const Camera& camera) const {
    std::vector<double> key = {double(int(camera.model())), double(camera.width()), double(camera.height())};
    key.insert(key.end(), camera.params().begin(), camera.params().end());
    {
      std::lock_guard<std::mutex> lock(centre_rays_mutex);
      if (auto it = centre_rays.find(key); it != centre_rays.end()) return it->second;
    }
    auto rays = std::make_shared<const PixelCentreRays>(ComputePixelCentreRays(camera));
    std::lock_guard<std::mutex> lock(centre_rays_mutex);
    if (centre_rays.size() >= kMaxCachedCameras) centre_rays.clear();
    centre_rays.emplace(std::move(key), rays);
    return rays;
  }

  // Rays go to Embree in streams, a batch's camera rays in one call and their shadow rays in
  // another, marked coherent: Embree then traverses neighbouring rays together in SIMD packets.
  // On the street that traces a frame's rays 4.5x as fast as one rtcIntersect1 / rtcOccluded1
  // call per ray (one thread: 31 ms against 140), hitting the same triangles at the same points.
  void Intersect(std::vector<RTCRayHit>& rays) const {
    if (rays.empty()) return;
    RTCIntersectContext context = CoherentContext();
    rtcIntersect1M(scene, &context, rays.data(), unsigned(rays.size()), sizeof(RTCRayHit));
  }

  void Occlude(std::vector<RTCRay>& rays) const {
    if (rays.empty()) return;
    RTCIntersectContext context = CoherentContext();
    rtcOccluded1M(scene, &context, rays.data(), unsigned(rays.size()), sizeof(RTCRay));
  }

  static RTCIntersectContext CoherentContext() {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    context.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
    return context;
  }

  // Everything about a camera ray's hit except the sun's shadow ray: shading a batch of hits
  // before tracing their shadow rays lets the CPU overlap the hits' independent chains of loads
  // and arithmetic instead of running each between two Embree traversals.
  [[gnu::always_inline]] void ShadeWithoutShadow(SampleRecord& r, const Eigen::Vector3f& origin,
                                                 const ShadeParams& p) const {
    const Hit& hit = r.hit;
    const MeshData& m = meshes[hit.geom];
    Eigen::Vector3f ng, n;
    SurfaceNormals(hit, r.dir, &ng, &n);
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
      r.shadow_origin = ShadowRayOrigin(hit, origin, r.dir, ng);
    }
  }

  // Radiance leaving the hit towards the camera, once its shadow ray (if any) is answered.
  [[gnu::always_inline]] Eigen::Vector3f FinishShading(SampleRecord& r, bool sun_visible) const {
    if (r.sun_ray && sun_visible) r.light += r.sun_light;
    const Eigen::Vector3f reflected = r.albedo * r.light;
    const MeshData& m = meshes[r.hit.geom];
    return m.emits ? Eigen::Vector3f(reflected + Emission(m, r)) : reflected;
  }

  // The shading normal `n` (facing the ray) turned by the mesh's normal map. The map's axes are
  // the triangle's tangent frame made orthogonal to n; its +Z is the surface's outside, so seen
  // from the back the whole frame turns over (out of line: rare, and it keeps the common path short).
  [[gnu::noinline]] static Eigen::Vector3f NormalMapped(const MeshData& m, const SampleRecord& r,
                                                        const Eigen::Vector3f& ng, const Eigen::Vector3f& n) {
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

  // How much of the sky the material's occlusion map lets through at the hit (out of line: rare,
  // and it keeps the common path short).
  [[gnu::noinline]] static float Occlusion(const MeshData& m, const SampleRecord& r, const Eigen::Vector3f& ng) {
    const Hit& hit = r.hit;
    const float open = m.occlusion_layer.Sample(hit.prim, hit.u, hit.v, FootprintMetres(hit, r.dir, r.angle, ng)).x();
    return 1.0f + m.occlusion_strength * (open - 1.0f);
  }

  // Pixel footprint on the surface (major axis), for the textures' mip levels: `angle` is the
  // ray's angular footprint, `ng` the geometric normal.
  [[gnu::always_inline]] static float FootprintMetres(const Hit& hit, const Eigen::Vector3f& dir, float angle,
                                                      const Eigen::Vector3f& ng) {
    return hit.t * angle / std::max(std::abs(ng.dot(dir)), 0.1f);
  }

  // What an emissive surface gives off towards the camera ray (out of line: rare, and it keeps
  // the common path short).
  [[gnu::noinline]] static Eigen::Vector3f Emission(const MeshData& m, const SampleRecord& r) {
    if (m.emissive_layer.texture == nullptr) return m.emissive;
    const Hit& hit = r.hit;
    Eigen::Vector3f ng = m.triangles[hit.prim].face_normal;  // the footprint ignores its sign
    if (ng.squaredNorm() == 0.0f) ng = -r.dir;                // as SurfaceNormals
    const Eigen::Vector4f texel = m.emissive_layer.Sample(hit.prim, hit.u, hit.v, FootprintMetres(hit, r.dir, r.angle, ng));
    return m.emissive.cwiseProduct(texel.head<3>());
  }

  // Geometric (ng) and shading (n) normals at a hit, both facing the incoming ray: surfaces are
  // lit from the side they are seen from.
  void SurfaceNormals(const Hit& hit, const Eigen::Vector3f& dir, Eigen::Vector3f* ng_out, Eigen::Vector3f* n_out) const {
    const MeshData& m = meshes[hit.geom];
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
  static bool NeedsSunRay(const Eigen::Vector3f& ng, const Eigen::Vector3f& n, const ShadeParams& p) {
    return n.dot(p.sun_dir) > 0 && ng.dot(p.sun_dir) > 0;
  }

  // Start of the shadow ray: the hit point offset along the geometric normal, scaled with float
  // precision at this distance.
  static Eigen::Vector3f ShadowRayOrigin(const Hit& hit, const Eigen::Vector3f& origin, const Eigen::Vector3f& dir,
                                         const Eigen::Vector3f& ng) {
    const Eigen::Vector3f point = origin + hit.t * dir;
    const float eps = 1e-4f * (1.0f + std::max(point.cwiseAbs().maxCoeff(), hit.t));
    return point + eps * ng;
  }
};

namespace {

// Sub-pixel offset in [-0.5, 0.5)^2 of sample `s` of pixel (x, y).
Eigen::Vector2d SampleOffset(uint64_t seed, int x, int y, int s, int spp, int grid, const std::vector<int>& rooks) {
  const float jx = UnitFloat(HashSample(seed, x, y, s, 0));
  const float jy = UnitFloat(HashSample(seed, x, y, s, 1));
  if (grid > 0) {
    return Eigen::Vector2d((s % grid + jx) / grid - 0.5, (s / grid + jy) / grid - 0.5);
  }
  return Eigen::Vector2d((s + jx) / spp - 0.5, (rooks[s] + jy) / spp - 0.5);
}

// A camera ray as Embree takes it, and a shadow ray (no hit record: only whether it is blocked).
RTCRayHit CameraRay(const Eigen::Vector3f& origin, const Eigen::Vector3f& dir) {
  RTCRayHit rh;
  rh.ray.org_x = origin.x();
  rh.ray.org_y = origin.y();
  rh.ray.org_z = origin.z();
  rh.ray.tnear = 0.0f;
  rh.ray.dir_x = dir.x();
  rh.ray.dir_y = dir.y();
  rh.ray.dir_z = dir.z();
  rh.ray.time = 0.0f;
  rh.ray.tfar = std::numeric_limits<float>::infinity();
  rh.ray.mask = ~0u;
  rh.ray.id = 0;
  rh.ray.flags = 0;
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  return rh;
}

RTCRay ShadowRay(const Eigen::Vector3f& origin, const Eigen::Vector3f& dir) {
  return CameraRay(origin, dir).ray;
}

bool IsOccluded(const RTCRay& ray) { return ray.tfar == -std::numeric_limits<float>::infinity(); }

// Where a camera ray of a batch belongs: its pixel in the tile, its angular footprint (texture
// filtering), and whether it is the pixel centre's ray or one of the colour samples.
struct CameraRayInfo {
  int pixel;
  float angle;
  bool centre;
};

// A view's camera rays, batch by batch (a run of pixels of one tile row), in the order Render
// traces them: for each pixel inside the lens its centre's ray (labels, instance, depth and, at
// 1 spp, the colour), then at spp > 1 the rays of its samples that fall inside the lens. One
// object per thread (it keeps a scratch permutation).
class CameraRays {
 public:
  CameraRays(const Camera& camera, const PixelCentreRays& centres, const Rigid3d& cam_from_world, const RenderOptions& options)
      : camera_(camera),
        centres_(centres),
        world_from_cam_(cam_from_world.rotation.conjugate()),
        world_from_cam_f_(world_from_cam_.toRotationMatrix().cast<float>()),
        origin_(cam_from_world.SourceOriginInTarget().cast<float>()),
        spp_(options.samples_per_pixel),
        seed_(options.seed) {
    grid_ = int(std::lround(std::sqrt(double(spp_))));
    if (grid_ * grid_ != spp_) grid_ = 0;  // n-rooks
    rooks_.resize(grid_ > 0 ? 0 : spp_);
  }

  const Eigen::Vector3f& origin() const { return origin_; }

  // Pixels [x_begin, x_end) of image row y, in the tile whose top-left pixel is `tile_corner`.
  void Batch(const Eigen::Vector2i& tile_corner, int y, int x_begin, int x_end, std::vector<RTCRayHit>* rays,
             std::vector<CameraRayInfo>* info) {
    rays->clear();
    info->clear();
    const int width = centres_.width;
    for (int x = x_begin; x < x_end; ++x) {
      const size_t idx = size_t(y) * width + x;
      if (!centres_.valid[idx]) continue;
      const int pixel = (y - tile_corner.y()) * kTileSize + (x - tile_corner.x());
      rays->push_back(CameraRay(origin_, world_from_cam_f_ * centres_.bearings[idx]));
      info->push_back({pixel, centres_.angle[idx], true});
      if (spp_ == 1) continue;
      if (grid_ == 0) {  // n-rooks: a per-pixel random permutation of the y strata
        for (int i = 0; i < spp_; ++i) rooks_[i] = i;
        for (int i = spp_ - 1; i > 0; --i) {
          const int j = int(HashSample(seed_, x, y, i, 2) % uint64_t(i + 1));
          std::swap(rooks_[i], rooks_[j]);
        }
      }
      const float sample_angle = centres_.angle[idx] / std::sqrt(float(spp_));
      for (int s = 0; s < spp_; ++s) {
        const Eigen::Vector2d offset = SampleOffset(seed_, x, y, s, spp_, grid_, rooks_);
        const auto bearing = camera_.CamFromImg(Eigen::Vector2d(x, y) + offset);
        if (!bearing) continue;  // part of the pixel lies outside the lens
        rays->push_back(CameraRay(origin_, (world_from_cam_ * *bearing).cast<float>().normalized()));
        info->push_back({pixel, sample_angle, false});
      }
    }
  }

 private:
  const Camera& camera_;
  const PixelCentreRays& centres_;
  Eigen::Quaterniond world_from_cam_;
  Eigen::Matrix3f world_from_cam_f_;
  Eigen::Vector3f origin_;
  int spp_;
  int grid_ = 0;
  uint64_t seed_;
  std::vector<int> rooks_;
};

// The top-left pixel of a tile; tiles are numbered row by row.
Eigen::Vector2i TileCorner(int tile, int width) {
  const int tiles_x = (width + kTileSize - 1) / kTileSize;
  return Eigen::Vector2i((tile % tiles_x) * kTileSize, (tile / tiles_x) * kTileSize);
}

// Calls f(y, x_begin, x_end) for each batch of the tile at `corner`: row by row, runs of at most
// PixelsPerBatch(spp) pixels, so that a batch's rays and shading records stay in L1.
template <class F>
void ForEachBatch(const Eigen::Vector2i& corner, int width, int height, int spp, F&& f) {
  const int x_end = std::min(width, corner.x() + kTileSize), y_end = std::min(height, corner.y() + kTileSize);
  const int batch_pixels = PixelsPerBatch(spp);
  for (int y = corner.y(); y < y_end; ++y) {
    for (int x = corner.x(); x < x_end; x += batch_pixels) f(y, x, std::min(x_end, x + batch_pixels));
  }
}

int NumTiles(int width, int height) {
  return ((width + kTileSize - 1) / kTileSize) * ((height + kTileSize - 1) / kTileSize);
}

// A traced batch's colour samples as shading records, in pixel order; `on_centre(info, ray)`
// sees every pixel's centre ray (labels, instance and depth).
template <class OnCentre>
void CollectRecords(const std::vector<RTCRayHit>& rays, const std::vector<CameraRayInfo>& info,
                    std::vector<SampleRecord>* records, OnCentre&& on_centre) {
  records->clear();
  auto add = [&](size_t i) {
    const RTCRayHit& rh = rays[i];
    SampleRecord& r = records->emplace_back();  // field by field: no wide copy over narrow stores
    r.hit.hit = rh.hit.geomID != RTC_INVALID_GEOMETRY_ID;
    r.hit.geom = rh.hit.geomID;
    r.hit.prim = rh.hit.primID;
    r.hit.u = rh.hit.u;
    r.hit.v = rh.hit.v;
    r.hit.t = rh.ray.tfar;
    r.dir = Eigen::Vector3f(rh.ray.dir_x, rh.ray.dir_y, rh.ray.dir_z);
    r.angle = info[i].angle;
    r.pixel = info[i].pixel;
  };
  for (size_t i = 0; i < rays.size();) {
    const size_t centre = i++;
    on_centre(info[centre], rays[centre]);
    const size_t first_sample = i;
    while (i < rays.size() && !info[i].centre) ++i;
    if (first_sample == i) add(centre);  // 1 spp, or every sample outside the lens
    for (size_t k = first_sample; k < i; ++k) add(k);
  }
}

// The shadow rays of a batch's shaded records, in record order.
void CollectShadowRays(const std::vector<SampleRecord>& records, const ShadeParams& p, std::vector<RTCRay>* shadow) {
  shadow->clear();
  if (!p.shadows) return;
  for (const SampleRecord& r : records) {
    if (r.hit.hit && r.sun_ray) shadow->push_back(ShadowRay(r.shadow_origin, p.sun_dir));
  }
}

ShadeParams ShadeParamsOf(const RenderOptions& options) {
  ShadeParams shade;
  shade.sun_dir = options.sun_direction_world.normalized().cast<float>();
  shade.sun_intensity = float(options.sun_intensity);
  shade.sky_intensity = float(options.sky_intensity);
  shade.shadows = options.shadows;
  return shade;
}

}  // namespace

// ---------------------------------------------------------------------------------------------

void RenderOptions::Check() const {
  auto fail = [](const std::string& why) { throw std::invalid_argument("invalid render options: " + why); };
  if (samples_per_pixel < 1 || samples_per_pixel > 65536) {
    fail("samples_per_pixel must be in 1..65536, got " + std::to_string(samples_per_pixel));
  }
  if (!sun_direction_world.allFinite() || sun_direction_world.norm() < 1e-12) {
    fail("sun_direction_world must be a finite non-zero vector");
  }
  if (!std::isfinite(sun_intensity) || sun_intensity < 0) fail("sun_intensity must be finite and >= 0");
  if (!std::isfinite(sky_intensity) || sky_intensity < 0) fail("sky_intensity must be finite and >= 0");
  if (!std::isfinite(exposure) || exposure <= 0) fail("exposure must be finite and > 0");
  if (num_threads < 0) fail("num_threads must be >= 0 (0 = all cores), got " + std::to_string(num_threads));
}

Renderer::Renderer(const Scene& scene) : impl_(std::make_unique<Impl>()) {
  const std::string source = scene.source.empty() ? std::string("scene") : scene.source;
  Impl& impl = *impl_;
  impl.scene_ptr = &scene;
  impl.source = source;

  impl.textures.reserve(scene.textures.size());  // MeshData points into it: no reallocation
  for (const Texture& texture : scene.textures) {
    impl.textures.push_back(BuildMipTexture(texture, TexelEncoding::kSrgb, source));
  }
  // Normal and occlusion maps hold data, not colour: their levels are built from the codes as
  // they are.
  for (const Material& material : scene.materials) {
    for (const int t : {material.normal_texture, material.occlusion_texture}) {
      if (t >= 0 && size_t(t) < scene.textures.size() && !impl.data_textures.count(t)) {
        impl.data_textures.emplace(t, BuildMipTexture(scene.textures[t], TexelEncoding::kLinear, source));
      }
    }
  }

  impl.device = rtcNewDevice(nullptr);
  if (impl.device == nullptr) {
    throw std::runtime_error(source + ": cannot create an Embree device (error " +
                             std::to_string(int(rtcGetDeviceError(nullptr))) + ")");
  }
  rtcSetDeviceErrorFunction(impl.device, &EmbreeErrors::Callback, &impl.errors);
  impl.BuildGeometry(scene.meshes);
}

void Renderer::SetMeshes(const std::vector<SceneMesh>& meshes) { impl_->BuildGeometry(meshes); }

void Renderer::Impl::BuildGeometry(const std::vector<SceneMesh>& scene_meshes) {
  const Scene& scene = *scene_ptr;
  Impl& impl = *this;
  if (impl.scene) {
    rtcReleaseScene(impl.scene);
    impl.scene = nullptr;
  }
  impl.meshes.clear();
  impl.meshes.shrink_to_fit();
  const std::string& source = impl.source;
  impl.meshes.resize(scene_meshes.size());
  for (size_t i = 0; i < scene_meshes.size(); ++i) {
    const SceneMesh& mesh = scene_meshes[i];
    const std::string where = source + ": mesh " + std::to_string(i) + " '" + mesh.name + "'";
    if (mesh.indices.size() % 3 != 0) throw std::invalid_argument(where + ": index count is not a multiple of 3");
    for (uint32_t index : mesh.indices) {
      if (index >= mesh.positions.size()) {
        throw std::invalid_argument(where + ": index " + std::to_string(index) + " >= " +
                                    std::to_string(mesh.positions.size()) + " positions");
      }
    }
    // Per-vertex attributes: none, or one per position.
    auto check_per_vertex = [&](size_t count, const char* what) {
      if (count != 0 && count != mesh.positions.size()) {
        throw std::invalid_argument(where + ": " + std::to_string(count) + " " + what + " for " +
                                    std::to_string(mesh.positions.size()) + " positions");
      }
    };
    check_per_vertex(mesh.normals.size(), "normals");
    check_per_vertex(mesh.texcoords.size(), "texcoords");
    check_per_vertex(mesh.normal_texcoords.size(), "normal-map texcoords");
    check_per_vertex(mesh.emissive_texcoords.size(), "emissive texcoords");
    check_per_vertex(mesh.occlusion_texcoords.size(), "occlusion texcoords");
    check_per_vertex(mesh.colors.size(), "vertex colours");
    if (mesh.material < -1 || mesh.material >= int(scene.materials.size())) {
      throw std::invalid_argument(where + ": material index " + std::to_string(mesh.material) + " out of range");
    }

    MeshData& m = impl.meshes[i];
    m.mesh = &mesh;
    m.class_id = mesh.class_id;
    m.instance_id = mesh.instance_id;
    if (mesh.material >= 0) {
      const Material& material = scene.materials[mesh.material];
      m.base_color = material.base_color_factor;
      auto check_texture = [&](int index, const char* what) {
        if (index >= int(scene.textures.size()) || index < -1) {
          throw std::invalid_argument(where + ": material '" + material.name + "' " + what + " index " +
                                      std::to_string(index) + " out of range");
        }
      };
      check_texture(material.base_color_texture, "texture");
      check_texture(material.emissive_texture, "emissive texture");
      check_texture(material.normal_texture, "normal texture");
      check_texture(material.occlusion_texture, "occlusion texture");
      if (material.base_color_texture >= 0 && !mesh.texcoords.empty()) {
        m.texture = &impl.textures[material.base_color_texture];
      }
      // A single-hit tracer cannot composite BLEND; cutting it out at the cutoff at least keeps
      // fully transparent texels (foliage cards, fences) from occluding.
      m.alpha_tested = material.alpha_mode != AlphaMode::kOpaque;
      m.alpha_cutoff = material.alpha_cutoff;
      m.unlit = material.unlit;
      m.emissive = material.emissive;
      m.emits = !material.unlit && material.emissive != Eigen::Vector3f::Zero();
      if (material.emissive_texture >= 0 && !mesh.emissive_texcoords.empty()) {
        m.emissive_layer.Build(&impl.textures[material.emissive_texture], mesh, mesh.emissive_texcoords);
      }
      if (material.occlusion_texture >= 0 && !mesh.occlusion_texcoords.empty() && !material.unlit) {
        m.occlusion_layer.Build(&impl.data_textures.at(material.occlusion_texture), mesh, mesh.occlusion_texcoords);
        m.occlusion_strength = material.occlusion_strength;
      }
      if (material.normal_texture >= 0 && !mesh.normal_texcoords.empty() && !material.unlit) {
        m.normal_layer.Build(&impl.data_textures.at(material.normal_texture), mesh, mesh.normal_texcoords);
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

  impl.scene = rtcNewScene(impl.device);
  impl.errors.ThrowIfAny(source + ": creating the Embree scene");
  // Watertight traversal: without it a ray through the edge two triangles share can miss both
  // and see what lies behind, a wrong label and depth in the ground truth (seen: 13 pixels of six
  // split quads whose diagonals pass through pixel centres, and on a triangle strip).
  rtcSetSceneFlags(impl.scene, RTC_SCENE_FLAG_ROBUST);

  for (size_t i = 0; i < scene_meshes.size(); ++i) {
    const SceneMesh& mesh = scene_meshes[i];
    if (mesh.indices.empty()) continue;  // nothing to hit; geomIDs stay equal to mesh indices
    RTCGeometry geom = rtcNewGeometry(impl.device, RTC_GEOMETRY_TYPE_TRIANGLE);
    auto* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                                 3 * sizeof(float), mesh.positions.size()));
    auto* indices = static_cast<unsigned*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                                   3 * sizeof(unsigned), mesh.indices.size() / 3));
    if (vertices == nullptr || indices == nullptr) {
      rtcReleaseGeometry(geom);
      impl.errors.ThrowIfAny(source + ": mesh '" + mesh.name + "'");
      throw std::runtime_error(source + ": mesh '" + mesh.name + "': Embree could not allocate buffers");
    }
    for (size_t v = 0; v < mesh.positions.size(); ++v) {
      vertices[3 * v] = mesh.positions[v].x();
      vertices[3 * v + 1] = mesh.positions[v].y();
      vertices[3 * v + 2] = mesh.positions[v].z();
    }
    std::copy(mesh.indices.begin(), mesh.indices.end(), indices);
    if (impl.meshes[i].alpha_tested) {
      rtcSetGeometryUserData(geom, &impl.meshes[i]);
      rtcSetGeometryIntersectFilterFunction(geom, &AlphaMaskFilter);
      rtcSetGeometryOccludedFilterFunction(geom, &AlphaMaskFilter);
    }
    rtcCommitGeometry(geom);
    rtcAttachGeometryByID(impl.scene, geom, unsigned(i));
    rtcReleaseGeometry(geom);  // the scene holds its own reference
  }
  rtcCommitScene(impl.scene);
  impl.errors.ThrowIfAny(source + ": building the Embree scene");
}

Renderer::~Renderer() = default;

RenderedView Renderer::Render(const Camera& camera, const Rigid3d& cam_from_world, const RenderOptions& options) const {
  options.Check();
  const Impl& impl = *impl_;
  const int width = camera.width(), height = camera.height();

  RenderedView view;
  view.rgb = ImageU8(width, height, 3, 0);
  view.label = ImageU8(width, height, 1, 0);
  view.instance = ImageU16(width, height, 1, 0);
  view.range = ImageF(width, height, 1, 0.0f);

  const ShadeParams shade = ShadeParamsOf(options);
  const float exposure = float(options.exposure);
  const SrgbEncodeTables& srgb = SrgbEncodeTables::Get();

  tbb::task_arena arena(options.num_threads > 0 ? options.num_threads : tbb::task_arena::automatic);
  arena.execute([&] {
    const std::shared_ptr<const PixelCentreRays> centres_ptr = impl.CentreRays(camera);
    const PixelCentreRays& centres = *centres_ptr;
    tbb::parallel_for(tbb::blocked_range<int>(0, NumTiles(width, height)), [&](const tbb::blocked_range<int>& tiles) {
      CameraRays camera_rays(camera, centres, cam_from_world, options);
      const Eigen::Vector3f& origin = camera_rays.origin();
      std::vector<RTCRayHit> rays;
      std::vector<CameraRayInfo> info;
      std::vector<SampleRecord> records;
      std::vector<RTCRay> shadow;
      TileOutputs out;
      for (int tile = tiles.begin(); tile < tiles.end(); ++tile) {
        const Eigen::Vector2i corner = TileCorner(tile, width);
        ForEachBatch(corner, width, height, options.samples_per_pixel, [&](int y, int x_begin, int x_end) {
          for (int x = x_begin; x < x_end; ++x) {
            if (!centres.valid[size_t(y) * width + x]) out.SetInvalid((y - corner.y()) * kTileSize + (x - corner.x()));
          }
          // 1. Camera rays, traced together: label, instance and depth from each pixel centre's ray.
          camera_rays.Batch(corner, y, x_begin, x_end, &rays, &info);
          impl.Intersect(rays);
          CollectRecords(rays, info, &records, [&](const CameraRayInfo& centre, const RTCRayHit& rh) {
            const bool hit = rh.hit.geomID != RTC_INVALID_GEOMETRY_ID;
            out.label[centre.pixel] = hit ? impl.meshes[rh.hit.geomID].class_id : kSkyId;
            out.instance[centre.pixel] = hit ? impl.meshes[rh.hit.geomID].instance_id : 0;
            out.range[centre.pixel] = hit ? rh.ray.tfar : 0.0f;
          });
          // 2. Shading without the sun: no rays traced, so the hits' work can overlap.
          for (SampleRecord& r : records) {
            if (r.hit.hit) impl.ShadeWithoutShadow(r, origin, shade);
          }
          // 3. Shadow rays, traced together, then each pixel's colour: the mean of its samples.
          CollectShadowRays(records, shade, &shadow);
          impl.Occlude(shadow);
          size_t next_shadow = 0;
          for (size_t i = 0; i < records.size();) {
            const int pixel = records[i].pixel;
            Eigen::Vector3f radiance = Eigen::Vector3f::Zero();
            int num_samples = 0;
            for (; i < records.size() && records[i].pixel == pixel; ++i, ++num_samples) {
              SampleRecord& r = records[i];
              if (!r.hit.hit) {
                radiance += SkyRadiance(r.dir, shade);
                continue;
              }
              const bool sun_visible = !(shade.shadows && r.sun_ray) || !IsOccluded(shadow[next_shadow++]);
              radiance += impl.FinishShading(r, sun_visible);
            }
            radiance *= exposure / float(num_samples);
            for (int c = 0; c < 3; ++c) out.rgb[3 * pixel + c] = SrgbCodeFromLinear(radiance[c], srgb);
          }
        });
        out.CopyTo(view, corner.x(), corner.y(), std::min(width - corner.x(), kTileSize),
                   std::min(height - corner.y(), kTileSize));
      }
    });
  });
  impl.errors.ThrowIfAny("rendering");
  return view;
}

std::shared_ptr<const std::vector<Eigen::Vector3f>> Renderer::PixelCentreBearings(const Camera& camera) const {
  const std::shared_ptr<const PixelCentreRays> rays = impl_->CentreRays(camera);
  return std::shared_ptr<const std::vector<Eigen::Vector3f>>(rays, &rays->bearings);  // keeps `rays` alive
}

// ---------------------------------------------------------------------------------------------

TraceOnlyStats Renderer::TraceOnlyForBenchmark(const Camera& camera, const Rigid3d& cam_from_world,
                                               const RenderOptions& options) const {
  options.Check();
  const Impl& impl = *impl_;
  const int width = camera.width(), height = camera.height();
  const ShadeParams shade = ShadeParamsOf(options);

  // Each batch's camera ray directions and shadow ray origins, found as Render finds them.
  struct Batch {
    std::vector<Eigen::Vector3f> camera_dirs;
    std::vector<Eigen::Vector3f> shadow_origins;
  };
  const int num_tiles = NumTiles(width, height);
  std::vector<std::vector<Batch>> batches(num_tiles);
  tbb::task_arena arena(options.num_threads > 0 ? options.num_threads : tbb::task_arena::automatic);
  arena.execute([&] {
    const std::shared_ptr<const PixelCentreRays> centres_ptr = impl.CentreRays(camera);
    tbb::parallel_for(0, num_tiles, [&](int tile) {
      CameraRays camera_rays(camera, *centres_ptr, cam_from_world, options);
      std::vector<RTCRayHit> rays;
      std::vector<CameraRayInfo> info;
      std::vector<SampleRecord> records;
      std::vector<RTCRay> shadow;
      const Eigen::Vector2i corner = TileCorner(tile, width);
      ForEachBatch(corner, width, height, options.samples_per_pixel, [&](int y, int x_begin, int x_end) {
        Batch& batch = batches[tile].emplace_back();
        camera_rays.Batch(corner, y, x_begin, x_end, &rays, &info);
        for (const RTCRayHit& rh : rays) batch.camera_dirs.emplace_back(rh.ray.dir_x, rh.ray.dir_y, rh.ray.dir_z);
        impl.Intersect(rays);
        CollectRecords(rays, info, &records, [](const CameraRayInfo&, const RTCRayHit&) {});
        for (SampleRecord& r : records) {
          if (r.hit.hit) impl.ShadeWithoutShadow(r, camera_rays.origin(), shade);
        }
        CollectShadowRays(records, shade, &shadow);
        for (const RTCRay& ray : shadow) batch.shadow_origins.emplace_back(ray.org_x, ray.org_y, ray.org_z);
      });
    });
  });

  TraceOnlyStats stats;
  for (const std::vector<Batch>& tile_batches : batches) {
    for (const Batch& batch : tile_batches) {
      stats.primary_rays += batch.camera_dirs.size();
      stats.shadow_rays += batch.shadow_origins.size();
    }
  }
  const Eigen::Vector3f origin = cam_from_world.SourceOriginInTarget().cast<float>();
  std::atomic<size_t> sink{0};  // keeps the results observable so nothing is optimised away
  const auto start = std::chrono::steady_clock::now();
  arena.execute([&] {
    tbb::parallel_for(0, num_tiles, [&](int tile) {
      size_t hits = 0;
      std::vector<RTCRayHit> rays;
      std::vector<RTCRay> shadow;
      for (const Batch& batch : batches[tile]) {
        rays.clear();
        for (const Eigen::Vector3f& dir : batch.camera_dirs) rays.push_back(CameraRay(origin, dir));
        impl.Intersect(rays);
        for (const RTCRayHit& rh : rays) hits += rh.hit.geomID != RTC_INVALID_GEOMETRY_ID;
        shadow.clear();
        for (const Eigen::Vector3f& o : batch.shadow_origins) shadow.push_back(ShadowRay(o, shade.sun_dir));
        impl.Occlude(shadow);
        for (const RTCRay& ray : shadow) hits += IsOccluded(ray);
      }
      sink += hits;
    });
  });
  stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  impl.errors.ThrowIfAny("tracing");
  return stats;
}

}  // namespace rigsim
