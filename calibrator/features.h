// Keypoints and descriptors (SIFT through OpenCV), optionally restricted to reliable classes.
//
// Keypoint positions use rigsim's pixel convention (geometry/camera_models.h): the centre of
// the top-left pixel is (0, 0), which is also OpenCV's, so no offset is applied.
#pragma once

#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "dataset/image.h"
#include "labels/cityscapes.h"

namespace rigsim {

struct FeatureOptions {
  // Strongest keypoints kept per image (by DoG response), counted after masking so that with a
  // mask the whole budget goes to reliable regions. 0 keeps all. Low-overlap rigs need many:
  // only the keypoints in the shared part of two views can match (measured on the demo ring:
  // 8000 -> 12000 with the lower contrast threshold below took the median pair rotation error
  // from 0.10-0.20 deg to 0.04-0.06 deg).
  int max_features = 12000;
  // SIFT scale-space layers per octave (OpenCV default 3).
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

  // Throws std::invalid_argument naming the first bad field.
  void Check() const;
};

struct Keypoint {
  Eigen::Vector2d px;  // pixel position (OpenCV convention)
  float size = 0.f;    // diameter of the meaningful neighbourhood (px)
  float angle = 0.f;   // orientation (deg, OpenCV's)
  uint8_t class_id = kUnlabeledId;  // label at the nearest pixel; kUnlabeledId without labels
};

struct FeatureSet {
  std::vector<Keypoint> keypoints;
  std::vector<float> descriptors;  // keypoints.size() x descriptor_size, row-major
  int descriptor_size = 0;

  int size() const { return static_cast<int>(keypoints.size()); }
  const float* descriptor(int i) const { return descriptors.data() + size_t(i) * descriptor_size; }
};

// Detects SIFT keypoints and descriptors in an RGB (or grey) image. `labels` (1 channel, same
// size, may be null) gives each keypoint its class. When `detect_only_on` is given, keypoints are
// detected only where the class is reliable (eroded mask, see FeatureOptions); it requires labels.
// Deterministic: keypoints are ordered by decreasing response, ties by position.
// Throws std::invalid_argument on bad inputs.
FeatureSet DetectFeatures(const ImageU8& rgb, const ImageU8* labels, const FeatureOptions& options,
                          const ReliableClasses* detect_only_on = nullptr);

}  // namespace rigsim
