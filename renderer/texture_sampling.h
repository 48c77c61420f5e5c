// Texture look-ups for shading: a box-filtered mip pyramid per texture and the filters a glTF
// sampler asks for (nearest, bilinear, the mip level's nearest or a trilinear blend).
//
// Conventions it relies on:
//   - Levels are stored in linear light with 16 bits per channel, at twice the memory of 8-bit sRGB
//     levels: filtering reads texels as they are instead of through a table look-up per channel,
//     and the levels are not re-quantised to 8-bit sRGB at every halving.
//   - Texture coordinates follow glTF: (0, 0) is the top-left corner of the image, texel centres
//     are at (i + 0.5) / width.
//   - The sampling functions are inline: shading calls them for every textured hit.
#pragma once

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <vector>

#include <Eigen/Core>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "scene/scene.h"

namespace rigsim {

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

// What a texture's RGB codes hold: colour (base colour, emission) in sRGB encoding, or data
// (normal maps) as they are.
enum class TexelEncoding { kSrgb, kLinear };

// The mip pyramid of `texture`, down to 1 x 1. The texture's size must match its bytes
// (scene/scene_validation.h).
MipTexture BuildMipTexture(const Texture& texture, TexelEncoding encoding);

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
inline TexelPair SampleNearest(const MipLevel& level, float s, float t) {
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
[[gnu::noinline]] TexelPair SampleMinifiedAsAsked(const MipTexture& tex, float s, float t, float lod);

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

// Level-0 texels per metre of a triangle whose corners p0..p2 map to t0..t2, for a texture with
// `texel_scale` texels per uv unit: sqrt(uv area / world area) * texel_scale (0 when degenerate).
float TexelsPerMetre(const Eigen::Vector3f& p0, const Eigen::Vector3f& p1, const Eigen::Vector3f& p2,
                     const Eigen::Vector2f& t0, const Eigen::Vector2f& t1, const Eigen::Vector2f& t2,
                     float texel_scale);

// The mip level to read for a footprint of `texels` level-0 texels (magnified when <= 0).
[[gnu::always_inline]] inline float LodOf(float texels) { return texels > 0 ? FastLog2(texels) : 0.0f; }

}  // namespace rigsim
