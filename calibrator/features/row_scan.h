// The scan that follows each block of brute-force L2 matching's product (matching.cc): from a row
// of -2 a.b and the norms, each squared distance, the row's nearest and second nearest and each
// column's nearest row so far. It costs more than the product it follows when run one value at a
// time, so the AVX2 and AVX-512 paths (cpu_path.h) scan 8 and 16 values per instruction. The scan
// only adds, takes maxima and compares, so every path gives the same bits.
#pragma once

#include "calibrator/features/cpu_path.h"

namespace rigsim {

// Nearest and second nearest of one row of squared distances: `index` the lowest index of the
// smallest value, `best` that value, `second` the second smallest counted with repetition (equal
// to `best` when the minimum occurs twice), as a plain left-to-right scan gives.
struct RowTop2 {
  int index;
  float best, second;
};

// Row i of the block (nb >= 2): d_j = max((minus_two_dot[j] + na2) + nb2[j], 0) for j < nb; every
// column whose d_j is below col_best_d2[j] takes it, and i as col_best[j] (strict '<': scanning rows
// in increasing order, a column's ties go to the lowest row); returns the row's top two. `path`
// must be one this CPU supports.
RowTop2 ScanRow(CpuPath path, const float* minus_two_dot, float na2, const float* nb2, int nb, int i,
                float* col_best_d2, int* col_best);

}  // namespace rigsim
