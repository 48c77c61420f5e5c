// A segmentation network run over every photo of a dataset, written in the layout calibrate reads
// with --labels DIR (dataset/label_source.h):
//
//   OUT/labels/<cam>/<frame>.png        uint8 Cityscapes label ids, the photo's size
//   OUT/labels_color/<cam>/<frame>.png  their colour preview (labels/cityscapes.h palette)
//   OUT/segmentation.json               the model, class table and pre-processing, seconds per
//                                       photo, the share of pixels per class and, on rendered
//                                       data, each class's IoU against the true labels
//
// The photos are each camera of rig.json (or, without rig.json, each folder of images/) at each
// frame of frames.json (or, without it, each photo of that camera's folder), as calibrate finds them.
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "segmentation/segmenter.h"

namespace rigsim {

struct SegmentedPhoto {
  std::string camera, frame;
  std::filesystem::path photo;
  std::filesystem::path truth;  // the dataset's labels/<cam>/<frame>.png (rendered data), or empty
};

// The photos of `dataset` in the order they are segmented (cameras, then frames), with their true
// labels where the dataset has them. Throws
// std::runtime_error naming the folder or file when there are none or one is missing.
std::vector<SegmentedPhoto> PhotosToSegment(const std::filesystem::path& dataset);

struct SegmentDatasetSummary {
  int photos = 0;
  double seconds = 0.0;            // the whole run: reading, network, writing
  double inference_seconds = 0.0;  // the network alone
  std::array<int, 2> first_input_size = {0, 0};  // the network input of the first photo
  std::map<uint8_t, int64_t> pixels_per_class;   // Cityscapes id -> pixel count, every photo

  // Against the true labels, over the photos that have them (rendered data).
  struct Agreement {
    int64_t truth = 0, network = 0, both = 0;  // pixels of the class in the truth, the network's, both
    double IoU() const { return truth + network - both > 0 ? double(both) / double(truth + network - both) : 0.0; }
  };
  int photos_with_truth = 0;
  std::map<uint8_t, Agreement> per_class;  // Cityscapes id -> agreement
  Agreement reliable;                      // the default reliable classes as one mask (what mask mode uses)
  int64_t pixels_compared = 0, pixels_agreeing = 0;
};

// Segments `photos` and writes OUT = `out_dir` (which the caller stages: StagedOutput). Calls
// `progress(done, total)` after each photo; an exception from it stops the run. Throws
// SegmenterError on a model that does not fit, std::runtime_error naming a photo that cannot be read.
SegmentDatasetSummary SegmentPhotos(const std::vector<SegmentedPhoto>& photos, const Segmenter& segmenter,
                                    const std::filesystem::path& out_dir,
                                    const std::function<void(int done, int total)>& progress = {});

}  // namespace rigsim
