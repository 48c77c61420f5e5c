#include "calibrator/features/row_scan.h"

#include <algorithm>
#include <limits>

// The AVX2 and AVX-512 scans are compiled for their instruction sets function by function (target
// attributes), as byte_product.cc's kernels are: the rest of the program stays at the baseline.
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#define RIGSIM_SCAN_KERNELS 1
#include <immintrin.h>
#else
#define RIGSIM_SCAN_KERNELS 0
#endif

namespace rigsim {
namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

// Lanes of the scan: value j goes to lane (j mod kLanes), and each lane keeps its own top two, so
// that a lane is a SIMD element instead of a chain of dependent compares.
constexpr int kLanes = 16;

struct Lanes {
  float b1[kLanes], b2[kLanes];  // each lane's smallest and second smallest
  int j1[kLanes];                // the index of b1 (-1: none yet)
};

// std::max(d, 0): rounding can make a squared distance slightly negative.
inline float Distance(const float* minus_two_dot, float na2, const float* nb2, int j) {
  return std::max((minus_two_dot[j] + na2) + nb2[j], 0.f);
}

// Value j (of `d`) in lane l, and column j's nearest row: strict '<' keeps the first of equal values.
inline void Visit(Lanes* s, int l, int j, float d, int i, float* col_best_d2, int* col_best) {
  const bool below = d < col_best_d2[j];
  col_best_d2[j] = below ? d : col_best_d2[j];
  col_best[j] = below ? i : col_best[j];
  const bool below1 = d < s->b1[l], below2 = d < s->b2[l];
  s->b2[l] = below1 ? s->b1[l] : (below2 ? d : s->b2[l]);
  s->j1[l] = below1 ? j : s->j1[l];
  s->b1[l] = below1 ? d : s->b1[l];
}

// The values from j0 on (fewer than kLanes) one at a time, then the lanes merged: the lane with the
// smallest value (ties: the lowest index) gives `index` and `best`, and `second` is the smallest of
// its second and the other lanes' smallest.
RowTop2 FinishScan(Lanes* s, int j0, const float* minus_two_dot, float na2, const float* nb2, int nb, int i,
                   float* col_best_d2, int* col_best) {
  for (int j = j0; j < nb; ++j) Visit(s, j - j0, j, Distance(minus_two_dot, na2, nb2, j), i, col_best_d2, col_best);
  int lane = 0;
  for (int l = 1; l < kLanes; ++l) {
    if (s->b1[l] < s->b1[lane] || (s->b1[l] == s->b1[lane] && s->j1[l] >= 0 && (s->j1[lane] < 0 || s->j1[l] < s->j1[lane]))) {
      lane = l;
    }
  }
  float second = s->b2[lane];
  for (int l = 0; l < kLanes; ++l) {
    if (l != lane) second = std::min(second, s->b1[l]);
  }
  return {s->j1[lane], s->b1[lane], second};
}

Lanes EmptyLanes() {
  Lanes s;
  std::fill(std::begin(s.b1), std::end(s.b1), kInf);
  std::fill(std::begin(s.b2), std::end(s.b2), kInf);
  std::fill(std::begin(s.j1), std::end(s.j1), -1);
  return s;
}

RowTop2 ScanRowBaseline(const float* __restrict minus_two_dot, float na2, const float* __restrict nb2, int nb, int i,
                        float* __restrict col_best_d2, int* __restrict col_best) {
  Lanes s = EmptyLanes();
  int j0 = 0;
  for (; j0 + kLanes <= nb; j0 += kLanes) {
    for (int l = 0; l < kLanes; ++l) {
      Visit(&s, l, j0 + l, Distance(minus_two_dot, na2, nb2, j0 + l), i, col_best_d2, col_best);
    }
  }
  return FinishScan(&s, j0, minus_two_dot, na2, nb2, nb, i, col_best_d2, col_best);
}

#if RIGSIM_SCAN_KERNELS
// max(0, x) is x unless 0 > x, as std::max(x, 0.f) (a -0 stays -0): MAXPS returns its second
// operand unless the first is greater.

RIGSIM_TARGET_AVX2 RowTop2 ScanRowAvx2(const float* minus_two_dot, float na2, const float* nb2, int nb, int i,
                                       float* col_best_d2, int* col_best) {
  constexpr int kWidth = 8;  // lanes per vector: two vectors hold the kLanes lanes
  const __m256 zero = _mm256_setzero_ps(), vna2 = _mm256_set1_ps(na2);
  const __m256i vi = _mm256_set1_epi32(i), step = _mm256_set1_epi32(kLanes);
  __m256 b1[2] = {_mm256_set1_ps(kInf), _mm256_set1_ps(kInf)}, b2[2] = {b1[0], b1[1]};
  __m256i j1[2] = {_mm256_set1_epi32(-1), _mm256_set1_epi32(-1)};
  __m256i jv[2] = {_mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7), _mm256_setr_epi32(8, 9, 10, 11, 12, 13, 14, 15)};
  int j0 = 0;
  for (; j0 + kLanes <= nb; j0 += kLanes) {
    for (int h = 0; h < 2; ++h) {
      const int j = j0 + h * kWidth;
      const __m256 d = _mm256_max_ps(
          zero, _mm256_add_ps(_mm256_add_ps(_mm256_loadu_ps(minus_two_dot + j), vna2), _mm256_loadu_ps(nb2 + j)));
      const __m256 cd = _mm256_loadu_ps(col_best_d2 + j);
      const __m256 col = _mm256_cmp_ps(d, cd, _CMP_LT_OQ);
      _mm256_storeu_ps(col_best_d2 + j, _mm256_blendv_ps(cd, d, col));
      auto* ci = reinterpret_cast<__m256i*>(col_best + j);
      _mm256_storeu_si256(ci, _mm256_blendv_epi8(_mm256_loadu_si256(ci), vi, _mm256_castps_si256(col)));
      const __m256 below1 = _mm256_cmp_ps(d, b1[h], _CMP_LT_OQ), below2 = _mm256_cmp_ps(d, b2[h], _CMP_LT_OQ);
      b2[h] = _mm256_blendv_ps(_mm256_blendv_ps(b2[h], d, below2), b1[h], below1);
      j1[h] = _mm256_blendv_epi8(j1[h], jv[h], _mm256_castps_si256(below1));
      b1[h] = _mm256_blendv_ps(b1[h], d, below1);
      jv[h] = _mm256_add_epi32(jv[h], step);
    }
  }
  Lanes s;
  for (int h = 0; h < 2; ++h) {
    _mm256_storeu_ps(s.b1 + h * kWidth, b1[h]);
    _mm256_storeu_ps(s.b2 + h * kWidth, b2[h]);
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(s.j1 + h * kWidth), j1[h]);
  }
  return FinishScan(&s, j0, minus_two_dot, na2, nb2, nb, i, col_best_d2, col_best);
}

RIGSIM_TARGET_AVX512 RowTop2 ScanRowAvx512(const float* minus_two_dot, float na2, const float* nb2, int nb, int i,
                                           float* col_best_d2, int* col_best) {
  const __m512 zero = _mm512_setzero_ps(), vna2 = _mm512_set1_ps(na2);
  const __m512i vi = _mm512_set1_epi32(i), step = _mm512_set1_epi32(kLanes);
  __m512 b1 = _mm512_set1_ps(kInf), b2 = b1;
  __m512i j1 = _mm512_set1_epi32(-1);
  __m512i jv = _mm512_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15);
  int j0 = 0;
  for (; j0 + kLanes <= nb; j0 += kLanes) {
    const __m512 d = _mm512_max_ps(
        zero, _mm512_add_ps(_mm512_add_ps(_mm512_loadu_ps(minus_two_dot + j0), vna2), _mm512_loadu_ps(nb2 + j0)));
    const __mmask16 col = _mm512_cmp_ps_mask(d, _mm512_loadu_ps(col_best_d2 + j0), _CMP_LT_OQ);
    _mm512_mask_storeu_ps(col_best_d2 + j0, col, d);
    _mm512_mask_storeu_epi32(col_best + j0, col, vi);
    const __mmask16 below1 = _mm512_cmp_ps_mask(d, b1, _CMP_LT_OQ), below2 = _mm512_cmp_ps_mask(d, b2, _CMP_LT_OQ);
    b2 = _mm512_mask_blend_ps(below1, _mm512_mask_blend_ps(below2, b2, d), b1);
    j1 = _mm512_mask_blend_epi32(below1, j1, jv);
    b1 = _mm512_mask_blend_ps(below1, b1, d);
    jv = _mm512_add_epi32(jv, step);
  }
  Lanes s;
  _mm512_storeu_ps(s.b1, b1);
  _mm512_storeu_ps(s.b2, b2);
  _mm512_storeu_si512(s.j1, j1);
  return FinishScan(&s, j0, minus_two_dot, na2, nb2, nb, i, col_best_d2, col_best);
}
#endif

}  // namespace

RowTop2 ScanRow(CpuPath path, const float* minus_two_dot, float na2, const float* nb2, int nb, int i,
                float* col_best_d2, int* col_best) {
#if RIGSIM_SCAN_KERNELS
  if (path == CpuPath::kAvx512Vnni) return ScanRowAvx512(minus_two_dot, na2, nb2, nb, i, col_best_d2, col_best);
  if (path == CpuPath::kAvx2) return ScanRowAvx2(minus_two_dot, na2, nb2, nb, i, col_best_d2, col_best);
#endif
  return ScanRowBaseline(minus_two_dot, na2, nb2, nb, i, col_best_d2, col_best);
}

}  // namespace rigsim
