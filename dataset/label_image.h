// Label images: Cityscapes ids <-> colour previews.
#pragma once

#include <filesystem>
#include <string>

#include "geometry/image.h"

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

enum class LabelImageFormat { kIds, kColors };

// Reads a label image a user or a network wrote, in either form, told apart by its channel count:
// 1 channel = Cityscapes label ids; 3 channels (or 4, alpha ignored; palette PNGs are expanded to
// RGB) = Cityscapes colours (labels/cityscapes.h palette, the colours of labels_color/). Returns
// label ids. Throws std::runtime_error naming the file when it is missing or unreadable, has 2 or
// more than 4 channels, is not `width` x `height` (checked first, when both are > 0), holds an id
// that is no Cityscapes id, or a colour that is not in the palette (with the first such pixel).
// Colours shared by several classes give the first (black = unlabeled, pole's grey = pole).
ImageU8 ReadLabelImageIdsOrColors(const std::filesystem::path& path, int width = 0, int height = 0,
                                  LabelImageFormat* format = nullptr);

}  // namespace rigsim
