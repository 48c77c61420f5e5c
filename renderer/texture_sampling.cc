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

// Each destination texel's source texels' per-axis weights (integers over `src` texels): the
// share of each source texel that the destination texel covers, texel i spanning
// [i * src / dst, (i + 1) * src / dst) in source texels. The sampler puts level l's texel i at
// (i + 0.5) / width_l, so a texel must average what lies around that point: where a level's
// size is odd, pairs (2i, 2i + 1) would centre texel i at (2i + 1) / width_(l-1) instead, and
// the texture would stretch away from its corner by up to a texel of the coarser level (4 % at
// level 5 of a 731-texel texture), more the farther it is seen: features would not stay on
// their surface from view to view.
struct AxisWeights {
  int first = 0;
  std::vector<int> weight;
};
std::vector<AxisWeights> CoverageWeights(int src, int dst) {
  std::vector<AxisWeights> out(dst);
  for (int i = 0; i < dst; ++i) {
    // In units of 1 / dst source texels: the destination texel is [i * src, (i + 1) * src).
    const int64_t begin = int64_t(i) * src, end = int64_t(i + 1) * src;
    out[i].first = int(begin / dst);
    for (int j = out[i].first; j < src && int64_t(j) * dst < end; ++j) {
      const int64_t overlap = std::min(end, int64_t(j + 1) * dst) - std::max(begin, int64_t(j) * dst);
      out[i].weight.push_back(int(overlap));
    }
  }
  return out;
}

// Averages each destination texel's footprint (in linear light, so distant textures do not
// darken): 2x2 blocks where a size is even, with fractional texels at the seams where it is odd.
// Integer weights, rounded once: the same bytes on every machine (and where both sizes are even,
// the same as (a + b + c + d + 2) / 4).
MipLevel Downsample(const MipLevel& src) {
  MipLevel dst(std::max(1, src.width / 2), std::max(1, src.height / 2));
  const std::vector<AxisWeights> wx = CoverageWeights(src.width, dst.width);
  const std::vector<AxisWeights> wy = CoverageWeights(src.height, dst.height);
  // Each axis's weights sum to the source's size (in 1 / dst texels).
  const uint64_t total = uint64_t(src.width) * uint64_t(src.height);
  for (int y = 0; y < dst.height; ++y) {
    for (int x = 0; x < dst.width; ++x) {
      uint64_t sum[4] = {0, 0, 0, 0};
      for (size_t b = 0; b < wy[y].weight.size(); ++b) {
        for (size_t a = 0; a < wx[x].weight.size(); ++a) {
          const uint64_t w = uint64_t(wx[x].weight[a]) * uint64_t(wy[y].weight[b]);
          const uint16_t* p = src.Texel(wx[x].first + int(a), wy[y].first + int(b));
          for (int c = 0; c < 4; ++c) sum[c] += w * p[c];
        }
      }
      uint16_t* out = dst.Texel(x, y);
      for (int c = 0; c < 4; ++c) out[c] = uint16_t((sum[c] + total / 2) / total);
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
