// Label images: Cityscapes ids <-> colour previews.
#pragma once

#include <filesystem>
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

// Reads a label image (1-channel uint8 of Cityscapes ids, e.g. labels/<cam>/<frame>.png) and
// checks it: throws std::runtime_error naming the file when it is missing, unreadable, not
// single-channel, not `width` x `height` (when both are > 0) or holds an id that is no Cityscapes id.
ImageU8 ReadLabelImage(const std::filesystem::path& path, int width = 0, int height = 0);

}  // namespace rigsim
