#include "calibrator/features/byte_product.h"

#include <algorithm>
#include <cstring>
#include <stdexcept>

// The kernels are compiled for their instruction sets function by function (target attributes),
// so the rest of the program stays at the x86-64 baseline and each runs only where the CPU has it.
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#define RIGSIM_BYTE_KERNELS 1
#include <immintrin.h>
#else
#define RIGSIM_BYTE_KERNELS 0
#endif

namespace rigsim {
namespace {

constexpr int kVnniGroup = 16;  // columns per 512-bit vector of int32 sums
constexpr int kVnniStep = 4;    // bytes per column per multiply-add
constexpr int kAvx2Group = 8;   // columns per 256-bit vector of int32 sums
constexpr int kAvx2Step = 2;    // 16-bit values per column per multiply-add

// Chunks of 8 VNNI groups or 16 AVX2 groups (128 columns, 16 or 32 KB of SIFT descriptors) stay in
// L1 while the rows pass.
constexpr int kChunkColumns = 128;

// Calls tile(r, rows_in_tile, g, groups_in_tile) over `rows` x `groups`, column chunk by column
// chunk, in tiles of up to kR rows and kG groups.
template <int kR, int kG, typename TileFn>
void ForEachTile(int rows, int groups, int group_columns, TileFn tile) {
  const int chunk = kChunkColumns / group_columns;
  for (int g0 = 0; g0 < groups; g0 += chunk) {
    const int g_end = std::min(groups, g0 + chunk);
    for (int r = 0; r < rows;) {
      const int rr = rows - r >= kR ? kR : 1;
      for (int g = g0; g < g_end;) {
        const int gg = g_end - g >= kG ? kG : 1;
        tile(r, rr, g, gg);
        g += gg;
      }
      r += rr;
    }
  }
}

#if RIGSIM_BYTE_KERNELS
// GCC 12's AVX-512 headers read an "undefined" vector inside _mm512_slli_epi32 and
// _mm512_cvtepi32_ps and warn about it where they are inlined.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wuninitialized"

// --- AVX-512 VNNI: an R x G tile (R rows of A, G groups of 16 columns) of sums a' . b, kept in
// registers over the whole descriptor. VNNI multiplies unsigned by signed bytes, so A is shifted
// to signed (a' = a - 128) and the caller adds back 128 * sum(b).
template <int R, int G>
RIGSIM_TARGET_VNNI inline void VnniTile(const int8_t* a, int a_stride, const uint8_t* b, int steps,
                                        const int32_t* sum128, float* out, size_t out_stride, int columns_left) {
  __m512i acc[R][G];
  for (int r = 0; r < R; ++r) {
    for (int g = 0; g < G; ++g) acc[r][g] = _mm512_setzero_si512();
  }
  const size_t group_bytes = size_t(steps) * 64;
  for (int q = 0; q < steps; ++q) {
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
    const __m512i s = _mm512_loadu_si512(sum128 + g * kVnniGroup);
    const int n = std::min(kVnniGroup, columns_left - g * kVnniGroup);
    const __mmask16 mask = n >= kVnniGroup ? __mmask16(0xFFFF) : __mmask16((1u << n) - 1);
    for (int r = 0; r < R; ++r) {
      const __m512i dot = _mm512_add_epi32(acc[r][g], s);
      const __m512 minus_two = _mm512_cvtepi32_ps(_mm512_sub_epi32(zero, _mm512_slli_epi32(dot, 1)));
      _mm512_mask_storeu_ps(out + size_t(r) * out_stride + g * kVnniGroup, mask, minus_two);
    }
  }
}

// `a` holds `rows` shifted rows of `a_stride` bytes; `b` the packed groups.
RIGSIM_TARGET_VNNI void VnniProduct(const int8_t* a, int a_stride, int rows, const uint8_t* b, int steps,
                                    const int32_t* sum128, int num_columns, float* out, size_t out_stride) {
  const int groups = (num_columns + kVnniGroup - 1) / kVnniGroup;
  const size_t group_bytes = size_t(steps) * 64;
  ForEachTile<4, 4>(rows, groups, kVnniGroup, [&](int r, int rr, int g, int gg) {
    const int8_t* ap = a + size_t(r) * a_stride;
    const uint8_t* bp = b + size_t(g) * group_bytes;
    const int32_t* sp = sum128 + size_t(g) * kVnniGroup;
    float* op = out + size_t(r) * out_stride + size_t(g) * kVnniGroup;
    const int left = num_columns - g * kVnniGroup;
    if (rr == 4 && gg == 4) VnniTile<4, 4>(ap, a_stride, bp, steps, sp, op, out_stride, left);
    else if (rr == 4) VnniTile<4, 1>(ap, a_stride, bp, steps, sp, op, out_stride, left);
    else if (gg == 4) VnniTile<1, 4>(ap, a_stride, bp, steps, sp, op, out_stride, left);
    else VnniTile<1, 1>(ap, a_stride, bp, steps, sp, op, out_stride, left);
  });
}

// --- AVX2: an R x G tile (R rows of A, G groups of 8 columns) of sums a . b over pairs of 16-bit
// values (_mm256_madd_epi16: two products and their sum per int32 lane, exact for bytes).
template <int R, int G>
RIGSIM_TARGET_AVX2 inline void Avx2Tile(const int16_t* a, int a_stride, const int16_t* b, int steps, float* out,
                                        size_t out_stride, int columns_left) {
  __m256i acc[R][G];
  for (int r = 0; r < R; ++r) {
    for (int g = 0; g < G; ++g) acc[r][g] = _mm256_setzero_si256();
  }
  const size_t group_values = size_t(steps) * 16;
  for (int q = 0; q < steps; ++q) {
    __m256i bv[G];
    for (int g = 0; g < G; ++g) {
      bv[g] = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(b + g * group_values + size_t(q) * 16));
    }
    for (int r = 0; r < R; ++r) {
      int32_t pair;
      std::memcpy(&pair, a + size_t(r) * a_stride + size_t(q) * 2, 4);
      const __m256i av = _mm256_set1_epi32(pair);
      for (int g = 0; g < G; ++g) acc[r][g] = _mm256_add_epi32(acc[r][g], _mm256_madd_epi16(bv[g], av));
    }
  }
  const __m256i zero = _mm256_setzero_si256();
  for (int g = 0; g < G; ++g) {
    const int n = std::min(kAvx2Group, columns_left - g * kAvx2Group);
    for (int r = 0; r < R; ++r) {
      const __m256 minus_two = _mm256_cvtepi32_ps(_mm256_sub_epi32(zero, _mm256_slli_epi32(acc[r][g], 1)));
      float* o = out + size_t(r) * out_stride + g * kAvx2Group;
      if (n >= kAvx2Group) {
        _mm256_storeu_ps(o, minus_two);
      } else {
        alignas(32) float lanes[kAvx2Group];
        _mm256_store_ps(lanes, minus_two);
        std::memcpy(o, lanes, sizeof(float) * n);
      }
    }
  }
}

RIGSIM_TARGET_AVX2 void Avx2Product(const int16_t* a, int a_stride, int rows, const int16_t* b, int steps,
                                    int num_columns, float* out, size_t out_stride) {
  const int groups = (num_columns + kAvx2Group - 1) / kAvx2Group;
  const size_t group_values = size_t(steps) * 16;
  // 4 x 2 tiles: 8 accumulators, 2 columns and a row value in the 16 registers.
  ForEachTile<4, 2>(rows, groups, kAvx2Group, [&](int r, int rr, int g, int gg) {
    const int16_t* ap = a + size_t(r) * a_stride;
    const int16_t* bp = b + size_t(g) * group_values;
    float* op = out + size_t(r) * out_stride + size_t(g) * kAvx2Group;
    const int left = num_columns - g * kAvx2Group;
    if (rr == 4 && gg == 2) Avx2Tile<4, 2>(ap, a_stride, bp, steps, op, out_stride, left);
    else if (rr == 4) Avx2Tile<4, 1>(ap, a_stride, bp, steps, op, out_stride, left);
    else if (gg == 2) Avx2Tile<1, 2>(ap, a_stride, bp, steps, op, out_stride, left);
    else Avx2Tile<1, 1>(ap, a_stride, bp, steps, op, out_stride, left);
  });
}
#pragma GCC diagnostic pop
#endif

int StepSize(CpuPath path) { return path == CpuPath::kAvx512Vnni ? kVnniStep : kAvx2Step; }

}  // namespace

bool ByteProductAvailable(CpuPath path) { return RIGSIM_BYTE_KERNELS && path != CpuPath::kBaseline; }

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

ByteProductColumns::ByteProductColumns(const FeatureSet& b, const std::vector<int>& rows, CpuPath path)
    : path_(path), num_columns_(static_cast<int>(rows.size())) {
  if (!ByteProductAvailable(path) || !CpuSupports(path)) {
    throw std::logic_error("ByteProductColumns: no integer kernel for the CPU path " + std::string(CpuPathName(path)));
  }
  const int step = StepSize(path);
  steps_ = (b.descriptor_size + step - 1) / step;
  if (path == CpuPath::kAvx512Vnni) {
    const int groups = (num_columns_ + kVnniGroup - 1) / kVnniGroup;
    packed_.assign(size_t(groups) * steps_ * 64, 0);
    sum128_.assign(size_t(groups) * kVnniGroup, 0);
    for (int j = 0; j < num_columns_; ++j) {
      const float* d = b.descriptor(rows[j]);
      uint8_t* group = packed_.data() + size_t(j / kVnniGroup) * steps_ * 64 + (j % kVnniGroup) * kVnniStep;
      int32_t sum = 0;
      for (int k = 0; k < b.descriptor_size; ++k) {
        const auto v = static_cast<uint8_t>(d[k]);
        group[size_t(k / kVnniStep) * 64 + k % kVnniStep] = v;
        sum += v;
      }
      sum128_[j] = 128 * sum;
    }
  } else {
    const int groups = (num_columns_ + kAvx2Group - 1) / kAvx2Group;
    packed16_.assign(size_t(groups) * steps_ * 16, 0);
    for (int j = 0; j < num_columns_; ++j) {
      const float* d = b.descriptor(rows[j]);
      int16_t* group = packed16_.data() + size_t(j / kAvx2Group) * steps_ * 16 + (j % kAvx2Group) * kAvx2Step;
      for (int k = 0; k < b.descriptor_size; ++k) group[size_t(k / kAvx2Step) * 16 + k % kAvx2Step] = int16_t(d[k]);
    }
  }
}

void ByteProductColumns::MinusTwoDot(const FeatureSet& a, const std::vector<int>& ia, size_t begin, size_t end,
                                     float* out, size_t out_stride) const {
  const int step = StepSize(path_);
  if ((a.descriptor_size + step - 1) / step != steps_) {
    throw std::invalid_argument("ByteProductColumns: descriptor sizes differ");
  }
  const int rows = static_cast<int>(end - begin);
  const int a_stride = steps_ * step;
#if RIGSIM_BYTE_KERNELS
  if (path_ == CpuPath::kAvx512Vnni) {
    std::vector<int8_t> shifted(size_t(rows) * a_stride, 0);  // a - 128; the padding stays 0
    for (int r = 0; r < rows; ++r) {
      const float* d = a.descriptor(ia[begin + r]);
      int8_t* row = shifted.data() + size_t(r) * a_stride;
      for (int k = 0; k < a.descriptor_size; ++k) row[k] = static_cast<int8_t>(int(d[k]) - 128);
    }
    VnniProduct(shifted.data(), a_stride, rows, packed_.data(), steps_, sum128_.data(), num_columns_, out, out_stride);
    return;
  }
  std::vector<int16_t> values(size_t(rows) * a_stride, 0);  // the padding stays 0
  for (int r = 0; r < rows; ++r) {
    const float* d = a.descriptor(ia[begin + r]);
    int16_t* row = values.data() + size_t(r) * a_stride;
    for (int k = 0; k < a.descriptor_size; ++k) row[k] = int16_t(d[k]);
  }
  Avx2Product(values.data(), a_stride, rows, packed16_.data(), steps_, num_columns_, out, out_stride);
#else
  (void)ia, (void)out, (void)out_stride, (void)rows, (void)a_stride;
  throw std::logic_error("ByteProductColumns: this build has no integer kernel");
#endif
}

}  // namespace rigsim
