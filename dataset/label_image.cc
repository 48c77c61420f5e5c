#include "dataset/label_image.h"

#include <stdexcept>

#include "dataset/image_io.h"
#include "labels/cityscapes.h"

namespace rigsim {

ImageU8 ColorizeLabels(const ImageU8& labels) {
  ImageU8 out(labels.width, labels.height, 3);
  for (int y = 0; y < labels.height; ++y) {
    for (int x = 0; x < labels.width; ++x) {
      const LabelClass* c = FindClassById(labels.at(x, y));
      for (int k = 0; k < 3; ++k) out.at(x, y, k) = c ? c->color[k] : 0;
    }
  }
  return out;
}

ImageU8 LabelsFromColors(const ImageU8& colors, const std::string& source) {
  if (colors.channels < 3) throw std::runtime_error(source + ": a colour label image needs 3 channels");
  ImageU8 out(colors.width, colors.height, 1);
  for (int y = 0; y < colors.height; ++y) {
    for (int x = 0; x < colors.width; ++x) {
      const std::array<uint8_t, 3> rgb = {colors.at(x, y, 0), colors.at(x, y, 1), colors.at(x, y, 2)};
      const auto id = ClassIdFromColor(rgb);
      if (!id) {
        throw std::runtime_error(source + ": pixel (" + std::to_string(x) + ", " + std::to_string(y) + ") has colour (" +
                                 std::to_string(rgb[0]) + ", " + std::to_string(rgb[1]) + ", " +
                                 std::to_string(rgb[2]) + "), which is no Cityscapes class colour");
      }
      out.at(x, y) = *id;
    }
  }
  return out;
}

void CheckLabelIds(const ImageU8& labels, const std::string& source) {
  for (int y = 0; y < labels.height; ++y) {
    for (int x = 0; x < labels.width; ++x) {
      if (!FindClassById(labels.at(x, y))) {
        throw std::runtime_error(source + ": pixel (" + std::to_string(x) + ", " + std::to_string(y) + ") has label id " +
                                 std::to_string(labels.at(x, y)) + ", which is no Cityscapes label id (0..33)");
      }
    }
  }
}

ImageU8 ReadLabelImage(const std::filesystem::path& path, int width, int height) {
  // Read with the file's own channel count: a colour preview passed as labels must not be
  // silently reduced to its red channel.
  const ImageU8 labels = ReadImageU8(path, 0);
  if (labels.channels != 1) {
    throw std::runtime_error(path.string() + ": a label image must have 1 channel of label ids, this one has " +
                             std::to_string(labels.channels));
  }
  if (width > 0 && height > 0 && !labels.SameSize(width, height)) {
    throw std::runtime_error(path.string() + ": label image is " + std::to_string(labels.width) + "x" +
                             std::to_string(labels.height) + ", expected " + std::to_string(width) + "x" +
                             std::to_string(height));
  }
  CheckLabelIds(labels, path.string());
  return labels;
}

ImageU8 ReadLabelImageIdsOrColors(const std::filesystem::path& path, int width, int height, LabelImageFormat* format) {
  const ImageU8 image = ReadImageU8(path, 0);
  if (image.channels == 2 || image.channels > 4) {
    throw std::runtime_error(path.string() + ": a label image must have 1 channel (Cityscapes label ids) or 3 "
                             "(Cityscapes colours), this one has " + std::to_string(image.channels));
  }
  if (width > 0 && height > 0 && !image.SameSize(width, height)) {
    throw std::runtime_error(path.string() + ": label image is " + std::to_string(image.width) + "x" +
                             std::to_string(image.height) + ", its image is " + std::to_string(width) + "x" +
                             std::to_string(height));
  }
  if (image.channels == 1) {
    CheckLabelIds(image, path.string());
    if (format) *format = LabelImageFormat::kIds;
    return image;
  }
  if (format) *format = LabelImageFormat::kColors;
  return LabelsFromColors(image, path.string());  // uses the first 3 channels
}

}  // namespace rigsim
