#include "pipeline/feature_cache.h"

#include "dataset/image_io.h"

namespace rigsim {

FeatureCache::FeatureCache(const DatasetLayout& layout, const Rig& rig, const FramesFile& frames,
                           const std::vector<std::filesystem::path>& image_paths, const std::vector<SemanticMode>& modes,
                           const FeatureOptions& features, const LabelIdSet& reliable, const LabelSource& labels,
                           int num_threads) {
  bool need_kind[2] = {false, false};
  bool need_labels = false;
  for (SemanticMode m : modes) {
    need_kind[Kind(m)] = true;
    need_labels = need_labels || NeedsLabels(m);
  }
  std::vector<int> kinds;
  std::vector<const LabelIdSet*> detect_only_on;
  for (int k = 0; k < 2; ++k) {
    if (!need_kind[k]) continue;
    kinds.push_back(k);
    detect_only_on.push_back(k == 1 ? &reliable : nullptr);
  }
  const int num_frames = static_cast<int>(frames.frames.size());
  const auto load = [&](int image) {
    const int cam = image / num_frames, frame = image % num_frames;
    const RigCamera& rc = rig.cameras[cam];
    LabelledImage out;
    out.rgb = ReadImageU8(image_paths[image], 3);
    // Checks size and Cityscapes ids or colours; names the file.
    if (need_labels) {
      out.labels = LoadLabels(labels, layout, rc.name, frames.frames[frame].name, rc.camera.width(), rc.camera.height());
    }
    return out;
  };
  std::vector<std::vector<double>> time_s;
  std::vector<std::vector<FeatureSet>> detected = DetectFeaturesInImages(
      static_cast<int>(image_paths.size()), load, features, detect_only_on, num_threads, &time_s);
  for (size_t i = 0; i < kinds.size(); ++i) {
    features_[kinds[i]] = std::move(detected[i]);
    time_s_[kinds[i]] = std::move(time_s[i]);
  }
}

double FeatureCache::DetectTimeS(SemanticMode m) const {
  double sum = 0.0;
  for (double t : time_s_[Kind(m)]) sum += t;
  return sum;
}

}  // namespace rigsim
