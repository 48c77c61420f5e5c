// Semantic pre-processing for calibration: which pixels may carry features (mask) and which
// keypoints may be matched with each other (gating), from a Cityscapes label image.
//
// The four modes the evaluation compares:
//   none        baseline: detect everywhere, match everything with everything
//   mask        detect only on reliable classes (the caller's choice of label ids: LabelIdSet;
//               rigsim's is labels/cityscapes.h ReliableClasses)
//   gated       detect everywhere, match only keypoints of the same class
//   mask+gated  both
#pragma once

#include <bitset>
#include <string>
#include <string_view>
#include <vector>

#include "geometry/image.h"

namespace rigsim {

enum class SemanticMode { kNone, kMask, kGated, kMaskGated };

inline constexpr SemanticMode kAllSemanticModes[] = {SemanticMode::kNone, SemanticMode::kMask,
                                                     SemanticMode::kGated, SemanticMode::kMaskGated};

// "none", "mask", "gated", "mask+gated".
std::string_view SemanticModeName(SemanticMode mode);
// Inverse of SemanticModeName; throws std::invalid_argument naming the accepted names.
SemanticMode SemanticModeFromName(std::string_view name);

inline bool UsesMask(SemanticMode m) { return m == SemanticMode::kMask || m == SemanticMode::kMaskGated; }
inline bool UsesGating(SemanticMode m) { return m == SemanticMode::kGated || m == SemanticMode::kMaskGated; }
inline bool NeedsLabels(SemanticMode m) { return m != SemanticMode::kNone; }

// A set of label ids, the values of a 1-channel label image: the classes the mask modes detect on.
using LabelIdSet = std::bitset<256>;

// Detection mask from a 1-channel label image: 255 where the class is reliable, 0 elsewhere,
// then eroded by `erosion_px` (a disc) so that no keypoint sits on a class boundary. The image
// border is not eroded: it is no class boundary.
ImageU8 ReliableMask(const ImageU8& labels, const LabelIdSet& reliable, int erosion_px);

}  // namespace rigsim
