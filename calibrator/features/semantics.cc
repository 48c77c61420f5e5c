#include "calibrator/features/semantics.h"

#include <stdexcept>

#include <opencv2/imgproc.hpp>

#include "common/did_you_mean.h"
#include "common/param_spec.h"

namespace rigsim {

std::string_view SemanticModeName(SemanticMode mode) {
  switch (mode) {
    case SemanticMode::kNone: return "none";
    case SemanticMode::kMask: return "mask";
    case SemanticMode::kGated: return "gated";
    case SemanticMode::kMaskGated: return "mask+gated";
  }
  return "?";
}

SemanticMode SemanticModeFromName(std::string_view name) {
  for (SemanticMode m : kAllSemanticModes) {
    if (SemanticModeName(m) == name) return m;
  }
  const std::vector<std::string> names = NamesOf(kAllSemanticModes, SemanticModeName);
  throw std::invalid_argument("unknown semantic mode '" + std::string(name) + "'" + DidYouMean(name, names) +
                              "; the modes are " + JoinNames(names));
}

ImageU8 ReliableMask(const ImageU8& labels, const LabelIdSet& reliable, int erosion_px) {
  if (labels.channels != 1) throw std::invalid_argument("ReliableMask: label image must have 1 channel");
  if (erosion_px < 0) throw std::invalid_argument("ReliableMask: erosion_px must be >= 0");
  ImageU8 mask(labels.width, labels.height, 1, 0);
  for (size_t i = 0; i < labels.data.size(); ++i) mask.data[i] = reliable[labels.data[i]] ? 255 : 0;
  if (erosion_px > 0 && !mask.empty()) {
    cv::Mat m(mask.height, mask.width, CV_8UC1, mask.data.data());
    const cv::Mat disc =
        cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(2 * erosion_px + 1, 2 * erosion_px + 1));
    // Default border value of erode is +inf: the image border does not eat into the mask.
    cv::erode(m, m, disc);
  }
  return mask;
}

}  // namespace rigsim
