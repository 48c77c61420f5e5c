// Label images: Cityscapes ids <-> colour previews.
#pragma once

#include <string>

#include "dataset/image.h"

namespace rigsim {

// 1-channel label ids -> 3-channel colour preview (unknown ids become black).
ImageU8 ColorizeLabels(const ImageU8& labels);

// 3-channel colour image -> label ids; throws std::runtime_error naming `source` and the first
// pixel whose colour is no Cityscapes colour.
ImageU8 LabelsFromColors(const ImageU8& colors, const std::string& source);

// Throws std::runtime_error naming `source` when a label id is not a Cityscapes id.
void CheckLabelIds(const ImageU8& labels, const std::string& source);

}  // namespace rigsim
