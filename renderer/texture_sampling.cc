#include "renderer/texture_sampling.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>

#include "renderer/srgb.h"

namespace rigsim {
namespace {

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

}  // namespace

MipTexture BuildMipTexture(const Texture& texture, TexelEncoding encoding) {
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

TexelPair SampleMinifiedAsAsked(const MipTexture& tex, float s, float t, float lod) {
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

float TexelsPerMetre(const Eigen::Vector3f& p0, const Eigen::Vector3f& p1, const Eigen::Vector3f& p2,
                     const Eigen::Vector2f& t0, const Eigen::Vector2f& t1, const Eigen::Vector2f& t2,
                     float texel_scale) {
  const float area2 = (p1 - p0).cross(p2 - p0).norm();
  if (!(area2 > 0)) return 0.0f;
  const Eigen::Vector2f e1 = t1 - t0, e2 = t2 - t0;
  return std::sqrt(std::abs(e1.x() * e2.y() - e1.y() * e2.x()) / area2) * texel_scale;
}

}  // namespace rigsim
