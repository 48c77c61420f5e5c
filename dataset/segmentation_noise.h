// A seeded model of the errors a semantic-segmentation network makes, applied to true label
// images, so that the semantic calibration modes can be measured with labels as a network would
// give them instead of perfect ones.
//
// Two kinds of error, applied in this order:
//
// 1. Blob-wise class confusion. The image is cut into superpixels: cells of a jittered grid of
//    about `blob_size_px` (each pixel goes to the nearest jittered cell centre, so cells are
//    irregular convex polygons). A blob is a 4-connected region of one class inside one cell. Each
//    blob whose class has confusable classes (labels/cityscapes.h ConfusableClasses) is relabelled,
//    with probability `confusion_rate`, to one of them (chosen uniformly). Networks err in patches:
//    a piece of a facade read as wall, a stretch of sidewalk as road. Void classes never change.
//
// 2. Boundary shift by N = boundary_px. Every class c gets a growth g_c(p) in [-(N+1)/2, (N+1)/2]
//    pixels: a per-image bias of the class (a network that favours vegetation grows it
//    everywhere) plus a smooth variation along the boundary (value noise, 32 px cells), half and
//    half. A pixel p of class L takes the class c within N px of it that minimises
//    d_c(p) - g_c(p), where d_c(p) is the distance from p to the nearest pixel of class c (0 for L
//    itself), keeping L on ties. The boundary between classes a and b thus moves by g_a - g_b in
//    whole pixels, capped at N, either way: one class dilates into the other by exactly what the
//    other erodes. Thin structures of a shrinking class (poles, distant signs) vanish, as they do
//    in real predictions. Only pixels within N px of a pixel of another class can change, and
//    only to such a class.
//
// Deterministic: every random choice is a hash of (seed, camera name, frame name) and the
// position or index it decides, so the same inputs give the same image whatever the thread count
// or the order in which images are processed. Zero boundary and zero confusion is the identity.
#pragma once

#include <cstdint>
#include <string_view>
#include <vector>

#include "geometry/image.h"

namespace rigsim {

struct SegmentationNoiseOptions {
  int boundary_px = 0;          // class boundaries move by up to this many pixels (0 = off)
  double confusion_rate = 0.0;  // probability that a blob is relabelled (0 = off)
  int blob_size_px = 48;        // superpixel cell size of the confusion blobs
  uint64_t seed = 0;

  bool IsIdentity() const { return boundary_px == 0 && confusion_rate == 0.0; }
  // Throws std::invalid_argument naming the bad field: boundary_px in [0, 64], confusion_rate in
  // [0, 1], blob_size_px in [4, 4096].
  void Check() const;
};

// The seed of one image: `seed` mixed with the camera and frame names.
uint64_t SegmentationNoiseImageSeed(uint64_t seed, std::string_view camera, std::string_view frame);

// The blobs step 1 relabels: per pixel (row-major) the index of its blob, blobs numbered in
// raster order of their first pixel.
struct LabelBlobs {
  std::vector<int> blob_of_pixel;
  std::vector<uint8_t> blob_class;  // label id of each blob
  int count() const { return static_cast<int>(blob_class.size()); }
};
LabelBlobs FindLabelBlobs(const ImageU8& labels, int blob_size_px, uint64_t image_seed);

// Applies both steps to a 1-channel label image. Throws std::invalid_argument on bad options or a
// label image that is not 1-channel.
ImageU8 ApplySegmentationNoise(const ImageU8& labels, const SegmentationNoiseOptions& options, uint64_t image_seed);
// The same with the image seed of (options.seed, camera, frame).
ImageU8 ApplySegmentationNoise(const ImageU8& labels, const SegmentationNoiseOptions& options, std::string_view camera,
                               std::string_view frame);

}  // namespace rigsim
