// Where the calibrator's semantic modes get their label images from:
//
//   truth   DATASET/labels/<cam>/<frame>.png, the labels the renderer wrote (1-channel ids)
//   folder  DIR/<cam>/<frame>.png written by the user or a network: Cityscapes label ids
//           (1 channel) or Cityscapes colours (RGB), detected per file by the channel count
//           (dataset/label_image.h ReadLabelImageIdsOrColors), so DATASET/labels_color works too
//   noisy   the truth through the segmentation-noise model (dataset/segmentation_noise.h),
//           seeded per (seed, camera, frame)
//
// Every label image is checked against its camera's image size and the Cityscapes ids or
// palette; errors name the file.
#pragma once

#include <filesystem>
#include <string>

#include "dataset/dataset.h"
#include "dataset/segmentation_noise.h"
#include "geometry/image.h"

namespace rigsim {

struct LabelSource {
  enum class Kind { kTruth, kFolder, kNoisy };
  Kind kind = Kind::kTruth;
  std::filesystem::path folder;    // kFolder
  SegmentationNoiseOptions noise;  // kNoisy

  static LabelSource Truth() { return {}; }
  static LabelSource Folder(std::filesystem::path dir) { return {Kind::kFolder, std::move(dir), {}}; }
  static LabelSource Noisy(const SegmentationNoiseOptions& noise) { return {Kind::kNoisy, {}, noise}; }

  // "truth", "folder" or "noisy".
  std::string KindName() const;
  // One line for logs: "truth", "folder /data/net_labels", "noisy (boundary 3 px, confusion 0.1, ...)".
  std::string Describe() const;
  // Throws std::invalid_argument on bad noise options, std::runtime_error naming the folder when a
  // label folder does not exist.
  void Check() const;
};

// The file the labels of (camera, frame) come from: the truth's for kTruth and kNoisy.
std::filesystem::path LabelSourcePath(const LabelSource& source, const DatasetLayout& layout, const std::string& camera,
                                      const std::string& frame);

// The checked 1-channel label-id image of (camera, frame), `width` x `height`. Throws
// std::runtime_error naming the file when it is missing ("label image missing"), of another size,
// or holds an unknown id or colour.
ImageU8 LoadLabels(const LabelSource& source, const DatasetLayout& layout, const std::string& camera,
                   const std::string& frame, int width, int height);

}  // namespace rigsim
