#include "calibrator/byte_product.h"

#include <algorithm>
#include <cstring>
#include <stdexcept>

#if defined(__AVX512VNNI__) && defined(__AVX512BW__) && defined(__AVX512F__)
#define RIGSIM_BYTE_PRODUCT 1
#include <immintrin.h>
#else
#define RIGSIM_BYTE_PRODUCT 0
#endif

namespace rigsim {
namespace {

constexpr int kGroup = 16;  // columns per 512-bit vector of int32 sums

#if RIGSIM_BYTE_PRODUCT
// GCC 12's AVX-512 headers read an "undefined" vector inside _mm512_slli_epi32 and
// _mm512_cvtepi32_ps and warn about it where they are inlined.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wuninitialized"
// An R x G tile (R rows of A, G groups of 16 columns) of sums a' . b, kept in registers over the
// whole descriptor. VNNI multiplies unsigned by signed bytes, so A is shifted to signed
// (a' = a - 128) and the caller adds back 128 * sum(b).
template <int R, int G>
inline void Tile(const int8_t* a, int a_stride, const uint8_t* b, int quads, const int32_t* sum128, float* out,
                 size_t out_stride, int columns_left) {
  __m512i acc[R][G];
  for (int r = 0; r < R; ++r) {
    for (int g = 0; g < G; ++g) acc[r][g] = _mm512_setzero_si512();
  }
  const size_t group_bytes = size_t(quads) * 64;
  for (int q = 0; q < quads; ++q) {
    __m512i bv[G];
    for (int g = 0; g < G; ++g) bv[g] = _mm512_loadu_si512(b + g * group_bytes + size_t(q) * 64);
    for (int r = 0; r < R; ++r) {
      int32_t quad;
      std::memcpy(&quad, a + size_t(r) * a_stride + size_t(q) * 4, 4);
      const __m512i av = _mm512_set1_epi32(quad);
      for (int g = 0; g < G; ++g) acc[r][g] = _mm512_dpbusd_epi32(acc[r][g], bv[g], av);
    }
  }
  const __m512i zero = _mm512_setzero_si512();
  for (int g = 0; g < G; ++g) {
    const __m512i s = _mm512_loadu_si512(sum128 + g * kGroup);
    const int n = std::min(kGroup, columns_left - g * kGroup);
    const __mmask16 mask = n >= kGroup ? __mmask16(0xFFFF) : __mmask16((1u << n) - 1);
    for (int r = 0; r < R; ++r) {
      const __m512i dot = _mm512_add_epi32(acc[r][g], s);
      const __m512 minus_two = _mm512_cvtepi32_ps(_mm512_sub_epi32(zero, _mm512_slli_epi32(dot, 1)));
      _mm512_mask_storeu_ps(out + size_t(r) * out_stride + g * kGroup, mask, minus_two);
    }
  }
}
#pragma GCC diagnostic pop
#endif

}  // namespace

bool ByteProductAvailable() { return RIGSIM_BYTE_PRODUCT != 0; }

bool DescriptorsAreBytes(const FeatureSet& f, const std::vector<int>& rows) {
  if (f.kind != DescriptorKind::kFloat) return false;
  for (int i : rows) {
    const float* d = f.descriptor(i);
    for (int k = 0; k < f.descriptor_size; ++k) {
      if (!(d[k] >= 0.f && d[k] <= 255.f) || d[k] != static_cast<float>(static_cast<int>(d[k]))) return false;
    }
  }
  return true;
}

ByteProductColumns::ByteProductColumns(const FeatureSet& b, const std::vector<int>& rows)
    : num_columns_(static_cast<int>(rows.size())), quads_((b.descriptor_size + 3) / 4) {
  if (!ByteProductAvailable()) throw std::logic_error("ByteProductColumns: this build has no integer kernel");
  const int groups = (num_columns_ + kGroup - 1) / kGroup;
  packed_.assign(size_t(groups) * quads_ * 64, 0);
  sum128_.assign(size_t(groups) * kGroup, 0);
  for (int j = 0; j < num_columns_; ++j) {
    const float* d = b.descriptor(rows[j]);
    uint8_t* group = packed_.data() + size_t(j / kGroup) * quads_ * 64 + (j % kGroup) * 4;
    int32_t sum = 0;
    for (int k = 0; k < b.descriptor_size; ++k) {
      const auto v = static_cast<uint8_t>(d[k]);
      group[size_t(k / 4) * 64 + k % 4] = v;
      sum += v;
    }
    sum128_[j] = 128 * sum;
  }
}

void ByteProductColumns::MinusTwoDot(const FeatureSet& a, const std::vector<int>& ia, size_t begin, size_t end,
                                     float* out, size_t out_stride) const {
#if RIGSIM_BYTE_PRODUCT
  if ((a.descriptor_size + 3) / 4 != quads_) throw std::invalid_argument("ByteProductColumns: descriptor sizes differ");
  const int rows = static_cast<int>(end - begin);
  const int a_stride = quads_ * 4;
  std::vector<int8_t> shifted(size_t(rows) * a_stride, 0);  // a - 128; the padding stays 0
  for (int r = 0; r < rows; ++r) {
    const float* d = a.descriptor(ia[begin + r]);
    int8_t* row = shifted.data() + size_t(r) * a_stride;
    for (int k = 0; k < a.descriptor_size; ++k) row[k] = static_cast<int8_t>(int(d[k]) - 128);
  }
  const int groups = (num_columns_ + kGroup - 1) / kGroup;
  const size_t group_bytes = size_t(quads_) * 64;
  // Chunks of 8 groups (128 columns, 16 KB of SIFT descriptors) stay in L1 while the rows pass.
  constexpr int kChunk = 8;
  for (int g0 = 0; g0 < groups; g0 += kChunk) {
    const int g_end = std::min(groups, g0 + kChunk);
    for (int r = 0; r < rows;) {
      const int rr = rows - r >= 4 ? 4 : 1;
      for (int g = g0; g < g_end;) {
        const int gg = g_end - g >= 4 ? 4 : 1;
        const int8_t* ap = shifted.data() + size_t(r) * a_stride;
        const uint8_t* bp = packed_.data() + size_t(g) * group_bytes;
        const int32_t* sp = sum128_.data() + size_t(g) * kGroup;
        float* op = out + size_t(r) * out_stride + size_t(g) * kGroup;
        const int left = num_columns_ - g * kGroup;
        if (rr == 4 && gg == 4) Tile<4, 4>(ap, a_stride, bp, quads_, sp, op, out_stride, left);
        else if (rr == 4) Tile<4, 1>(ap, a_stride, bp, quads_, sp, op, out_stride, left);
        else if (gg == 4) Tile<1, 4>(ap, a_stride, bp, quads_, sp, op, out_stride, left);
        else Tile<1, 1>(ap, a_stride, bp, quads_, sp, op, out_stride, left);
        g += gg;
      }
      r += rr;
    }
  }
#else
  (void)a, (void)ia, (void)begin, (void)end, (void)out, (void)out_stride;
  throw std::logic_error("ByteProductColumns: this build has no integer kernel");
#endif
}

}  // namespace rigsim
