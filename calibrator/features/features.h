// Keypoints and descriptors (SIFT, RootSIFT, ORB or AKAZE through OpenCV), optionally
// restricted to reliable classes.
//
// Keypoint positions use rigsim's pixel convention (geometry/camera_models.h): the centre of
// the top-left pixel is (0, 0), which is also OpenCV's, so no offset is applied.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Core>

#include "calibrator/features/semantics.h"
#include "geometry/image.h"

namespace rigsim {

// Which detector and descriptor. SIFT and RootSIFT give float descriptors matched by L2 distance;
// ORB and AKAZE (MLDB) give binary descriptors matched by Hamming distance (matching.h).
//  - kRootSift: SIFT descriptors L1-normalised, then square-rooted element-wise (Arandjelovic &
//    Zisserman 2012): L2 between them is the Hellinger kernel of the SIFT histograms, which
//    matches better than L2 on the raw histograms. Same keypoints as SIFT.
//  - kOrb: FAST corners + oriented BRIEF, 256 bits.
//  - kAkaze: nonlinear scale space, MLDB descriptor (486 bits); the free substitute for SURF.
enum class FeatureType { kSift, kRootSift, kOrb, kAkaze };

inline constexpr FeatureType kAllFeatureTypes[] = {FeatureType::kSift, FeatureType::kRootSift, FeatureType::kOrb,
                                                   FeatureType::kAkaze};

// "sift", "rootsift", "orb", "akaze" (the CLI's names).
std::string_view FeatureTypeName(FeatureType type);
// Inverse of FeatureTypeName; throws std::invalid_argument naming the accepted names.
FeatureType FeatureTypeFromName(std::string_view name);

struct FeatureOptions {
  FeatureType type = FeatureType::kSift;
  // Strongest keypoints kept per image (by detector response: DoG for SIFT, Harris for ORB, Hessian
  // for AKAZE), counted after masking so that with a mask the whole budget goes to reliable
  // regions. 0 keeps all. For ORB it is the detector's own budget (spread over its pyramid
  // levels), which OpenCV fills inside the mask. Low-overlap rigs need many: only the keypoints
  // in the shared part of two views can match (VALIDATION.md, "Where the calibrator's thresholds
  // come from").
  int max_features = 12000;
  // SIFT and RootSIFT: scale-space layers per octave (OpenCV default 3).
  int octave_layers = 3;
  // SIFT contrast threshold on the DoG (OpenCV's default is 0.04); lower finds more, weaker
  // keypoints, which the ratio test and the robust fit then sort out.
  double contrast_threshold = 0.02;
  // SIFT edge-response threshold (OpenCV default 10); higher keeps more edge-like keypoints.
  double edge_threshold = 10.0;
  // Blur of the base image (OpenCV default 1.6).
  double sigma = 1.6;
  // Erosion (px) of the reliable-class mask. Keypoints on a class boundary are mostly on an
  // occlusion contour (building against sky): not a fixed 3D point, and half their descriptor
  // window sees the background, which changes between views. A few pixels remove those without
  // emptying thin classes (poles, signs).
  int mask_erosion_px = 3;
  // ORB's FAST threshold (OpenCV default 20); the pyramid is OpenCV's (scale 1.2, 8 levels).
  int orb_fast_threshold = 20;
  // AKAZE detector response threshold (OpenCV default 0.001); lower finds more keypoints.
  double akaze_threshold = 0.001;

  // Throws std::invalid_argument naming the first bad field.
  void Check() const;
};

struct Keypoint {
  Eigen::Vector2d px;  // pixel position (OpenCV convention)
  float size = 0.f;    // diameter of the meaningful neighbourhood (px)
  float angle = 0.f;   // orientation (deg, OpenCV's)
  uint8_t class_id = 0;  // label id at the nearest pixel; 0 (unlabelled) without labels
};

// Float descriptors are compared by L2 distance, binary ones by Hamming distance; the two never
// mix (MatchFeatures refuses).
enum class DescriptorKind { kFloat, kBinary };

struct FeatureSet {
  std::vector<Keypoint> keypoints;
  DescriptorKind kind = DescriptorKind::kFloat;
  // kFloat: keypoints.size() x descriptor_size floats, row-major.
  std::vector<float> descriptors;
  // kBinary: keypoints.size() x descriptor_size bytes, row-major, bits packed as OpenCV packs them.
  std::vector<uint8_t> binary_descriptors;
  int descriptor_size = 0;  // floats (kFloat) or bytes (kBinary) per descriptor
  // Keypoints the detector found where the rig's own mask hides the image (DetectFeatures'
  // `rig_mask`), dropped. SIFT, RootSIFT and AKAZE detect everywhere and drop them, so this is what
  // the mask removed; ORB spends its budget inside the mask, finds none there and counts 0.
  int removed_by_mask = 0;

  int size() const { return static_cast<int>(keypoints.size()); }
  const float* descriptor(int i) const { return descriptors.data() + size_t(i) * descriptor_size; }
  const uint8_t* binary_descriptor(int i) const { return binary_descriptors.data() + size_t(i) * descriptor_size; }
  // The first n keypoints with their descriptors, of either kind (DetectFeatures orders them
  // strongest first, so this is the n strongest). The whole set when it has n or fewer.
  FeatureSet Head(int n) const;
};

// Detects keypoints and descriptors of `options.type` in an RGB (or grey) image; every detector
// runs on the 8-bit grey image. `labels` (1 channel, same size, may be null) gives each keypoint
// its class. When `detect_only_on` is given, keypoints are detected only where the class is
// reliable (eroded mask, see FeatureOptions; checked again at each keypoint's pixel, since ORB
// applies the mask on its downscaled pyramid levels); it requires labels.
// `rig_mask` (1 channel, the image's size, may be null) hides what moves with the rig, its own
// vehicle: no keypoint is kept where it is 0, whatever `detect_only_on` says, and the budget
// (max_features) goes to the rest.
// Deterministic: keypoints are ordered by decreasing response, ties by position.
// Throws std::invalid_argument on bad inputs.
FeatureSet DetectFeatures(const ImageU8& rgb, const ImageU8* labels, const FeatureOptions& options,
                          const LabelIdSet* detect_only_on = nullptr, const ImageU8* rig_mask = nullptr);

// An image to detect features in, its label image (empty when there is none) and its camera's
// rig mask (DetectFeatures' `rig_mask`; null when there is none; it outlives the detection).
struct LabelledImage {
  ImageU8 rgb;
  ImageU8 labels;
  const ImageU8* rig_mask = nullptr;
};

// The features of `num_images` images, detected in parallel (parallel_scope.h): each image is
// obtained once from `load` (called from worker threads; what it throws is rethrown) and detected
// once per entry of `detect_only_on` (nullptr: everywhere; a set: on those classes only, which
// needs labels), as DetectFeatures, with the image's rig mask for every entry. Returns
// [entry][image]; with `time_s`, each detection's time (s) in the same shape. `images_done`, when
// given, is told how many images are done after each one, one call at a time, counting up.
std::vector<std::vector<FeatureSet>> DetectFeaturesInImages(int num_images,
                                                           const std::function<LabelledImage(int)>& load,
                                                           const FeatureOptions& options,
                                                           const std::vector<const LabelIdSet*>& detect_only_on,
                                                           int num_threads = 0,
                                                           std::vector<std::vector<double>>* time_s = nullptr,
                                                           const std::function<void(int done)>& images_done = nullptr);

}  // namespace rigsim
