// Every view's features of a dataset, detected once per kind and shared by the semantic modes:
// none and gated detect everywhere, mask and mask+gated only on the reliable classes; the rig's
// own masks (rig_masks.h), when given, hide their cameras' vehicle from every kind. Each photo
// (and its labels, when a mode needs them, from the run's label source) is read once for every
// kind.
#pragma once

#include <filesystem>
#include <functional>
#include <vector>

#include "calibrator/features/features.h"
#include "calibrator/features/semantics.h"
#include "dataset/dataset.h"
#include "dataset/label_source.h"
#include "geometry/rig.h"
#include "pipeline/rig_masks.h"

namespace rigsim {

class FeatureCache {
 public:
  // Detects the features of the photos `image_paths` (camera-major: camera * frames + frame) of
  // the cameras of `rig` at `frames`, for the kinds `modes` use, each camera's with its mask in
  // `masks` (may be null; checked against the rig by ReadRigMasks); `photos_done`, when given, is
  // told how many photos are done after each (DetectFeaturesInImages). Throws std::runtime_error
  // naming a photo or label image that cannot be read.
  FeatureCache(const DatasetLayout& layout, const Rig& rig, const FramesFile& frames,
               const std::vector<std::filesystem::path>& image_paths, const std::vector<SemanticMode>& modes,
               const FeatureOptions& features, const LabelIdSet& reliable, const LabelSource& labels, int num_threads,
               const RigMasks* masks = nullptr, const std::function<void(int done)>& photos_done = nullptr);

  // Mode m's features, per view (camera * frames + frame).
  const std::vector<FeatureSet>& Of(SemanticMode m) const { return features_[Kind(m)]; }
  // The time mode m's features took to detect, summed over the images.
  double DetectTimeS(SemanticMode m) const;
  // Per camera of the rig, the keypoints mode m's detection found under the camera's mask and
  // dropped, summed over its frames (FeatureSet::removed_by_mask).
  std::vector<int> RemovedByMask(SemanticMode m) const;

 private:
  static int Kind(SemanticMode m) { return UsesMask(m) ? 1 : 0; }
  std::vector<FeatureSet> features_[2];  // unmasked, masked; empty when no mode uses the kind
  std::vector<double> time_s_[2];
  int num_cameras_ = 0, num_frames_ = 0;
};

}  // namespace rigsim
