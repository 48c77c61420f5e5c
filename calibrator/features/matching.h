// Descriptor matching between two feature sets: exact nearest neighbours (L2 for float
// descriptors, Hamming for binary ones), Lowe's ratio test and a mutual check, optionally gated by
// semantic class.
//
// Gating: keypoints are grouped by class and each class of A is matched only against the same
// class of B. The ratio test then compares against the second-best candidate *of that class*:
// that is the method under test (fewer candidates, fewer look-alikes), not an accident.
#pragma once

#include <cstdint>
#include <vector>

#include "calibrator/features/features.h"

namespace rigsim {

struct MatchOptions {
  // Lowe's ratio test: keep when best distance < ratio * second-best distance. A keypoint with
  // fewer than two candidates is rejected: its distinctiveness cannot be tested.
  double ratio = 0.8;
  // Keep a -> b only when a is also b's nearest neighbour among A's candidates.
  bool mutual = true;
  // Match only keypoints of the same class_id (the "gated" semantic modes; the pairwise stage sets it).
  bool gate_by_class = false;
  // Rows of A per block of the distance computation; bounds memory to block_rows * |B| floats
  // (L2: 12 MB for 12000 keypoints, under glibc's largest heap block, so that the next call reuses
  // it instead of page-faulting a fresh mapping). The Hamming path streams B once per block.
  int block_rows = 256;

  // Throws std::invalid_argument naming the first bad field.
  void Check() const;
};

struct Match {
  int a = -1;            // keypoint index in A
  int b = -1;            // keypoint index in B
  float distance = 0.f;  // L2 descriptor distance, or Hamming distance (bits) for binary descriptors
};

struct MatchStats {
  double time_s = 0.0;               // wall time of this call
  int64_t distance_evaluations = 0;  // descriptor pairs compared (the cost gating reduces)
  int ratio_passed = 0;              // A keypoints passing the ratio test
  int mutual_rejected = 0;           // of those, removed by the mutual check
};

// Matches ordered by A's index. Dispatches on the descriptor kind: L2 by a blocked matrix product
// for float descriptors, Hamming by popcount over 64-bit words for binary ones. Exact brute force
// either way, so the result is deterministic and does not depend on the thread count; ties go to
// the lowest index. Throws std::invalid_argument when the descriptor kinds differ (float against
// binary: no meaningful distance) or the descriptor sizes differ.
std::vector<Match> MatchFeatures(const FeatureSet& a, const FeatureSet& b, const MatchOptions& options,
                                 MatchStats* stats = nullptr);

}  // namespace rigsim
